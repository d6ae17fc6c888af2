"""Every class of character the text rule refuses beyond control characters (issue 27 item 5), one or
two of each, with the rule the API names: shared by the API's, the pages' and the command line's tests."""

from __future__ import annotations

INVISIBLE_CLASSES: dict[str, tuple[str, str]] = {
    "soft hyphen": ("\u00ad", "format_character"),
    "function application": ("\u2061", "format_character"),
    "invisible plus": ("\u2064", "format_character"),
    "inhibit symmetric swapping": ("\u206a", "format_character"),
    "nominal digit shapes": ("\u206f", "format_character"),
    "Mongolian vowel separator": ("\u180e", "format_character"),
    "interlinear annotation anchor": ("\ufff9", "format_character"),
    "interlinear annotation terminator": ("\ufffb", "format_character"),
    "line separator": ("\u2028", "separator_character"),
    "paragraph separator": ("\u2029", "separator_character"),
    "language tag": ("\U000e0001", "tag_character"),
    "tag letter": ("\U000e0041", "tag_character"),
    "cancel tag": ("\U000e007f", "tag_character"),
    "private use": ("\ue000", "private_use_character"),
    "supplementary private use": ("\U00100000", "private_use_character"),
    "Hangul filler": ("\u3164", "invisible_character"),
    "Hangul choseong filler": ("\u115f", "invisible_character"),
    "Hangul jungseong filler": ("\u1160", "invisible_character"),
    "halfwidth Hangul filler": ("\uffa0", "invisible_character"),
    "Braille pattern blank": ("\u2800", "invisible_character"),
    "variation selector": ("\ufe0f", "invisible_character"),
}
# Digits a person may type that are not 0-9: a number must be written in ASCII digits.
FOREIGN_DIGITS = {
    "Arabic-Indic": "\u0662\u0660\u0661\u0662",  # ٢٠١٢
    "Extended Arabic-Indic": "\u06f2\u06f0\u06f1\u06f2",  # ۲۰۱۲
    "fullwidth": "\uff12\uff10\uff11\uff12",  # ２０１２
}


def named(char: str) -> str:
    """What the refusal must say of the character: `U+00AD (SOFT HYPHEN)`, or `U+E000 (PRIVATE USE)`."""
    import unicodedata

    name = unicodedata.name(char, "") or "PRIVATE USE"
    return f"U+{ord(char):04X} ({name})"
