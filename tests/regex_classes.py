"""Each regex character class turned into a Hypothesis strategy once per run, not once per use.

The text rule's pattern (app/text.py) is one negated class of some 400,000 code points, and Hypothesis
builds a class's strategy one code point at a time: 3 to 13 s each time on CI. Schemathesis builds it
again for every bound it merges into the pattern (`{1,1}`, `{0,59}`, ...), 13 times while collecting
tests/api/test_schemathesis.py alone. The strategy of a class depends only on the class, the regex
flags and the alphabet, so it is kept and reused: the same strategy, hence the same examples.

Should Hypothesis rename what this wraps, nothing is kept and the tests are only slower.
"""

from __future__ import annotations

import re
from typing import Any

from hypothesis.strategies import SearchStrategy


def keep_character_classes() -> None:
    """Wrap Hypothesis's regex-to-strategy step so that a character class is built once (idempotent)."""
    # Imported here, once the session has started: at import it reads Hypothesis's Unicode tables,
    # which Hypothesis asks plugins and conftests not to do while pytest starts.
    from hypothesis.strategies._internal import regex as hypothesis_regex

    build = getattr(hypothesis_regex, "_strategy", None)
    if build is None or getattr(build, "keeps_character_classes", False):
        return
    character_class = re._constants.IN  # re's parser's name for `[...]`
    kept: dict[tuple[str, int, bool, str], SearchStrategy[Any]] = {}

    def strategy(codes: Any, context: Any, is_unicode: bool, *, alphabet: Any) -> SearchStrategy[Any]:
        if not (isinstance(codes, tuple) and codes[0] == character_class):
            return build(codes, context, is_unicode, alphabet=alphabet)  # type: ignore[no-any-return]
        key = (repr(codes[1]), int(context.flags), is_unicode, repr(alphabet))
        if key not in kept:
            kept[key] = build(codes, context, is_unicode, alphabet=alphabet)
        return kept[key]

    strategy.keeps_character_classes = True  # type: ignore[attr-defined]
    hypothesis_regex._strategy = strategy
