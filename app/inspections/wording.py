"""The verdict in words a non-engineer understands, from the stored loading-case verdicts."""

from __future__ import annotations

from collections.abc import Sequence

_NUMBERS = (
    "no",
    "one",
    "two",
    "three",
    "four",
    "five",
    "six",
    "seven",
    "eight",
    "nine",
    "ten",
    "eleven",
    "twelve",
)


def number_word(count: int) -> str:
    """one, two, ... twelve; larger counts as digits."""
    return _NUMBERS[count] if 0 <= count < len(_NUMBERS) else str(count)


def passengers(count: int) -> str:
    """'one passenger', 'two passengers'."""
    return f"{number_word(count)} passenger{'' if count == 1 else 's'}"


def occupancy(occupants: int) -> str:
    """A loading case in words: 'the driver alone', 'the driver and two passengers'."""
    if occupants <= 0:
        return "nobody aboard"
    if occupants == 1:
        return "the driver alone"
    return f"the driver and {passengers(occupants - 1)}"


def certified_occupancy(max_compliant_occupants: int) -> str:
    """The certified maximum occupancy: 'compliant with the driver alone'."""
    if max_compliant_occupants <= 0:
        return "not compliant even with the driver alone"
    if max_compliant_occupants == 1:
        return "compliant with the driver alone"
    return f"compliant with the driver and up to {passengers(max_compliant_occupants - 1)}"


def verdict_sentence(cases: Sequence[tuple[int, bool]], max_compliant_occupants: int) -> str:
    """The overall verdict in one or two sentences, from (occupants, compliant) per loading case."""
    occupied = [(n, ok) for n, ok in cases if n > 0]
    if all(ok for _n, ok in cases):
        most = max((n for n, _ok in occupied), default=0)
        return f"Compliant. Laterally stable in every loading case, up to {occupancy(most)}."
    best = max_compliant_occupants
    failing = [n for n, ok in occupied if not ok]
    if best == 0:
        return "Not compliant. Laterally unstable even with the driver alone."
    reach = occupancy(best) if best == 1 else f"the driver and up to {passengers(best - 1)}"
    stable = f"Laterally stable with {reach}"
    if not failing:
        return f"Not compliant. {stable}; unstable when empty."
    unstable = f"the driver and {passengers(min(failing) - 1)}"
    if failing == [n for n, _ok in occupied if n >= min(failing)]:
        if max(failing) > min(failing):
            unstable = f"the driver and {number_word(min(failing) - 1)} or more passengers"
    else:
        unstable = " or ".join(occupancy(n) for n in failing)
    return f"Not compliant. {stable}; unstable with {unstable}."
