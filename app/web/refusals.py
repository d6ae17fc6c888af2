"""The core's and services' refusals, as a page shows them beside a field, in the active language.

The stability core speaks English only (it imports nothing of the app) and the JSON API keeps its
English messages byte for byte, so a page translates a refusal when it shows it: each known sentence
is matched, its words translated and its figures (numbers, plates, units) carried over as they are.
A sentence not known here stays English, never empty.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from app.i18n.active import N_, current_locale, gettext
from app.i18n.locales import ENGLISH

# The things the core names in its sentences ("the front wheel reaction must be ..."), to translate.
THINGS = frozenset(
    {
        N_("front wheel reaction"),
        N_("left front wheel reaction"),
        N_("right front wheel reaction"),
        N_("left rear wheel reaction"),
        N_("right rear wheel reaction"),
        N_("rear wheel reaction"),
        N_("overall weight"),
        N_("wheelbase"),
        N_("standard occupant mass"),
        N_("distance behind the front wheel centre"),
        N_("load item mass"),
    }
)
_THING = "(?P<what>[a-z ]+?)"
_FIGURE = r"(?P<%s>-?[0-9][0-9.]*)"


def _figure(name: str) -> str:
    return _FIGURE % name


# (pattern of the English sentence, its message id with the same placeholders). Each message id
# is the English sentence with %(name)s where the pattern has a group, so English reads the same.
_SENTENCES: tuple[tuple[re.Pattern[str], str], ...] = tuple(
    (re.compile(pattern + "$"), message)
    for pattern, message in (
        (
            rf"The {_THING} must be more than {_figure('minimum')} and at most {_figure('maximum')} "
            rf"(?P<unit>kg|m); got {_figure('value')}",
            N_("The %(what)s must be more than %(minimum)s and at most %(maximum)s %(unit)s; got %(value)s"),
        ),
        (
            rf"The {_THING} must be at least {_figure('minimum')} and at most {_figure('maximum')} "
            rf"(?P<unit>kg|m); got {_figure('value')}",
            N_("The %(what)s must be at least %(minimum)s and at most %(maximum)s %(unit)s; got %(value)s"),
        ),
        (
            rf"Give the {_THING} to at most {_figure('decimals')} decimal places",
            N_("Give the %(what)s to at most %(decimals)s decimal places"),
        ),
        (
            rf"Enter the {_THING} as a finite number of (?P<unit>kg|m)",
            N_("Enter the %(what)s as a finite number of %(unit)s"),
        ),
        (
            rf"Give at least one reading of the {_THING}",
            N_("Give at least one reading of the %(what)s"),
        ),
        (
            rf"At most {_figure('count')} repeated readings are accepted",
            N_("At most %(count)s repeated readings are accepted"),
        ),
        (
            rf"The (?P<wheels>two|three|four) wheel readings add up to {_figure('wheel_sum')} kg but the "
            rf"overall weight is {_figure('overall')} kg; the difference \({_figure('share')} %\) is more "
            rf"than the allowed {_figure('allowed')} %\. Weigh the vehicle again\.",
            N_(
                "The %(wheels)s wheel readings add up to %(wheel_sum)s kg but the overall weight is "
                "%(overall)s kg; the difference (%(share)s %%) is more than the allowed %(allowed)s %%. "
                "Weigh the vehicle again."
            ),
        ),
        (r"Give at least the driver's seat", N_("Give at least the driver's seat")),
        (
            rf"At most {_figure('count')} seats are accepted",
            N_("At most %(count)s seats are accepted"),
        ),
        (
            r"(?P<plate>[A-Z0-9 ]+) is already registered",
            N_("%(plate)s is already registered"),
        ),
        (
            r"Use 2 to 16 letters and digits, like BDG 252 QH \(spaces and hyphens are ignored\)",
            N_("Use 2 to 16 letters and digits, like BDG 252 QH (spaces and hyphens are ignored)"),
        ),
        # The accounts' refusals (app/accounts/service.py), beside the user forms' boxes.
        (rf"Use at least {_figure('count')} characters", N_("Use at least %(count)s characters")),
        (
            r"Enter the person's name as certificates should print it",
            N_("Enter the person's name as certificates should print it"),
        ),
        (
            rf"Keep the name to {_figure('maximum')} characters \(it has {_figure('count')}\)",
            N_("Keep the name to %(maximum)s characters (it has %(count)s)"),
        ),
        (
            r"Use letters, spaces and punctuation only \(no control or invisible characters\)",
            N_("Use letters, spaces and punctuation only (no control or invisible characters)"),
        ),
        (
            rf"Use up to {_figure('maximum')} letters, digits, spaces, '\.', '/' or '-', like NSCDC/4471",
            N_("Use up to %(maximum)s letters, digits, spaces, '.', '/' or '-', like NSCDC/4471"),
        ),
        (r"An account for (?P<email>\S+) already exists", N_("An account for %(email)s already exists")),
        # The second factor's and a re-confirmation's refusals (app/accounts/second_factor.py, reauth.py).
        (
            r"That code is not right or was used already; enter the 6-digit code your app shows now",
            N_("That code is not right or was used already; enter the 6-digit code your app shows now"),
        ),
        (
            rf"Too many wrong codes; wait {_figure('minutes')} minutes, then try again",
            N_("Too many wrong codes; wait %(minutes)s minutes, then try again"),
        ),
        (
            rf"Too many wrong passwords; wait {_figure('minutes')} minutes, then try again",
            N_("Too many wrong passwords; wait %(minutes)s minutes, then try again"),
        ),
        (r"That is not your password", N_("That is not your password")),
        # A station's name taken (app/stations/service.py).
        (r"A station named (?P<name>'.*') already exists", N_("A station named %(name)s already exists")),
        # A type assessment's refusals (app/type_assessments/service.py, app/stability/type_assessment.py).
        (
            rf"A type assessment needs inspections of at least two vehicles of the (?P<model>.+); found "
            rf"{_figure('count')}",
            N_(
                "A type assessment needs inspections of at least two vehicles of the %(model)s; "
                "found %(count)s"
            ),
        ),
        (
            rf"More than {_figure('count')} vehicles of this model; choose the inspections",
            N_("More than %(count)s vehicles of this model; choose the inspections"),
        ),
        (
            r"(?P<first>.+) and (?P<second>.+) differ in (?P<differ>[a-z ]+); a type assessment needs "
            r"vehicles with one seat layout, wheelbase, load items and occupant mass",
            N_(
                "%(first)s and %(second)s differ in %(differ)s; a type assessment needs vehicles with one "
                "seat layout, wheelbase, load items and occupant mass"
            ),
        ),
        (
            r"The inspection of (?P<plate>.+) has loading cases weighed directly; a type assessment averages "
            r"the empty-vehicle readings, so choose an inspection without them",
            N_(
                "The inspection of %(plate)s has loading cases weighed directly; a type assessment averages "
                "the empty-vehicle readings, so choose an inspection without them"
            ),
        ),
    )
)
# Words inside a sentence that are themselves translated (the things, the count of wheels).
# What two vehicles of a type assessment may differ in (app/stability/type_assessment.py).
DIFFERENCES = frozenset(
    {N_("axle layout"), N_("seat layout"), N_("wheelbase"), N_("load items"), N_("occupant mass")}
)
_WORD_GROUPS: dict[str, Callable[[str], str]] = {
    "what": lambda word: gettext(word) if word in THINGS else word,
    "wheels": lambda word: gettext(word),
    "differ": lambda word: gettext(word) if word in DIFFERENCES else word,
}
N_("two")
N_("three")
N_("four")


def translated_refusal(message: str) -> str:
    """A refusal (without its field path) in the active language; English, or unknown, unchanged."""
    if current_locale() == ENGLISH:
        return message
    for pattern, message_id in _SENTENCES:
        match = pattern.match(message)
        if match is None:
            continue
        words = match.groupdict()
        if "what" in words and words["what"] not in THINGS:
            return message
        for name, translate in _WORD_GROUPS.items():
            if name in words:
                words[name] = translate(words[name])
        translated = gettext(message_id) % words
        # A sentence may open with the thing it names ("Ìwúwo ... gbọ́dọ̀ ..."): a capital, as readable() gives.
        return translated[:1].upper() + translated[1:]
    return message
