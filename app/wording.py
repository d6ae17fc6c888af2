"""Every fact in words, one function each: used by the pages, the PDF, the verify page, the CLI and the API.

Numbers follow the GOV.UK style: "one", then numerals (2, 3, ... 12).
"""

from __future__ import annotations

from collections.abc import Sequence
from decimal import Decimal
from fractions import Fraction
from typing import Literal

from app.i18n.active import N_, current_locale, ngettext
from app.i18n.active import gettext as _
from app.stability.layout import DELTA, LAYOUTS, Layout
from app.stability.model import layout_of_rules
from app.stability.remedies import Advice

DocumentKind = Literal["compliant", "refusal"]
DocumentStatus = Literal["issued", "revoked", "superseded", "expired"]


def number_word(count: int) -> str:
    """'one' for 1, numerals otherwise: one, 2, 3 ... (GOV.UK style); digits in every other language."""
    return "one" if count == 1 and current_locale() == "en" else str(count)


def passengers(count: int) -> str:
    """'one passenger', '2 passengers'."""
    return ngettext("one passenger", "%(count)s passengers", count) % {"count": count}


def _driver_and(count: int) -> str:
    """'the driver and one passenger', 'the driver and 2 passengers'."""
    return ngettext("the driver and one passenger", "the driver and %(count)s passengers", count) % {
        "count": count
    }


def occupancy(occupants: int) -> str:
    """One loading case in words: 'the driver alone', 'the driver and 2 passengers'."""
    if occupants <= 0:
        return _("nobody aboard")
    if occupants == 1:
        return _("the driver alone")
    return _driver_and(occupants - 1)


def occupancy_limit(max_compliant_occupants: int) -> str:
    """The most a vehicle may carry: 'the driver alone', 'the driver and up to 2 passengers'."""
    if max_compliant_occupants <= 1:
        return _("the driver alone")
    count = max_compliant_occupants - 1
    return ngettext(
        "the driver and up to one passenger", "the driver and up to %(count)s passengers", count
    ) % {"count": count}


def occupancy_sentence(compliant: bool, max_compliant_occupants: int) -> str:
    """The occupancy sentence: 'Certified for the driver and up to 2 passengers', or what a refusal allows."""
    if compliant and max_compliant_occupants >= 1:
        if max_compliant_occupants == 1:
            return _("Certified for the driver alone: no passengers")
        return _("Certified for %(occupancy)s") % {"occupancy": occupancy_limit(max_compliant_occupants)}
    if max_compliant_occupants <= 0:
        return _("This vehicle must not be used: it is unstable even with the driver alone")
    if max_compliant_occupants == 1:
        return _("This vehicle must not carry passengers")
    return _("This vehicle may carry %(occupancy)s, no more") % {
        "occupancy": occupancy_limit(max_compliant_occupants)
    }


def verdict_mark(compliant: bool) -> Literal["C", "NC"]:
    """A loading case's (or a document's) verdict as the study's Table 4 marks it: 'C' or 'NC'."""
    return "C" if compliant else "NC"


def verdict_sentence(cases: Sequence[tuple[int, bool]], max_compliant_occupants: int) -> str:
    """The overall verdict in one or two sentences, from (occupants, compliant) per loading case."""
    occupied = [(n, ok) for n, ok in cases if n > 0]
    if all(ok for _n, ok in cases):
        most = max((n for n, _ok in occupied), default=0)
        return _("Compliant. Laterally stable in every loading case, up to %(occupancy)s.") % {
            "occupancy": occupancy(most)
        }
    best = max_compliant_occupants
    failing = [n for n, ok in occupied if not ok]
    if best == 0:
        return _("Not compliant. Laterally unstable even with the driver alone.")
    stable = occupancy_limit(best)
    if not failing:
        return _("Not compliant. Laterally stable with %(stable)s; unstable when empty.") % {"stable": stable}
    fewest = min(failing) - 1
    unstable = _driver_and(fewest)
    if failing == [n for n, _ok in occupied if n >= min(failing)]:
        if max(failing) > min(failing):
            unstable = ngettext(
                "the driver and one or more passengers", "the driver and %(count)s or more passengers", fewest
            ) % {"count": fewest}
    else:
        unstable = occupancy(failing[0])
        for n in failing[1:]:
            unstable = _("%(these)s or %(those)s") % {"these": unstable, "those": occupancy(n)}
    return _("Not compliant. Laterally stable with %(stable)s; unstable with %(unstable)s.") % {
        "stable": stable,
        "unstable": unstable,
    }


def document_kind(kind: str) -> str:
    """What the document is called in a sentence: 'certificate' or 'refusal'."""
    return "certificate" if kind == "compliant" else "refusal"


def document_title(kind: str) -> str:
    """The document's title: 'Lateral Stability Certificate' or 'Lateral Stability Refusal'."""
    return _("Lateral Stability Certificate") if kind == "compliant" else _("Lateral Stability Refusal")


def issued_message(kind: str, number: str, created: bool) -> str:
    """The message after asking for a document: 'Refusal TRK-... issued.' or 'Already issued: ...'."""
    if kind == "compliant":
        message = (
            _("Certificate %(number)s issued.") if created else _("Already issued: certificate %(number)s.")
        )
    else:
        message = _("Refusal %(number)s issued.") if created else _("Already issued: refusal %(number)s.")
    return message % {"number": number}


def revoked_message(kind: str, number: str) -> str:
    """The message after revoking: 'Certificate TRK-... revoked.'."""
    message = (
        _("Certificate %(number)s revoked.") if kind == "compliant" else _("Refusal %(number)s revoked.")
    )
    return message % {"number": number}


def status_headline(kind: str, status: str) -> str:
    """The verify banner's headline: VALID CERTIFICATE, NOT CERTIFIED: refusal, REVOKED, EXPIRED..."""
    if status == "issued":
        return _("VALID CERTIFICATE") if kind == "compliant" else _("NOT CERTIFIED: refusal")
    words = {"revoked": N_("REVOKED"), "superseded": N_("SUPERSEDED"), "expired": N_("EXPIRED")}
    return _(words[status]) if status in words else status.upper()


def status_tone(kind: str, status: str) -> Literal["valid", "refused", "revoked", "lapsed"]:
    """The banner's colour: green only for a certificate in force; red refused/revoked; grey lapsed."""
    if status == "issued":
        return "valid" if kind == "compliant" else "refused"
    return "revoked" if status == "revoked" else "lapsed"


def status_meaning(status: str) -> str:
    """A public status (certified, refused, revoked, superseded, expired) in a few words: what a reader
    may do with the paper (the command line, the offline check)."""
    return _(_MEANINGS[status])


_MEANINGS = {
    "certified": N_("a certificate in force: the vehicle is certified as below"),
    "refused": N_("a refusal: the vehicle is NOT certified"),
    "revoked": N_("REVOKED: it certifies nothing"),
    "superseded": N_("SUPERSEDED: only the newer document counts"),
    "expired": N_("EXPIRED: the vehicle must be weighed again"),
}


# Marked here, translated where they are said (gettext at call time).
QR_GENUINE = N_("The QR code is genuine")
QR_NOT_GENUINE = N_("The QR code is NOT genuine: do not rely on this paper")


def status_headline_on(kind: str, status: str, since: str | None) -> str:
    """The headline with its date for a lapsed document: 'REVOKED on 3 December 2026'."""
    headline = status_headline(kind, status)
    if since and status != "issued":
        return _("%(headline)s on %(date)s") % {"headline": headline, "date": since}
    return headline


_QR_REASONS = {
    "bad_signature": N_("its content was changed, or it was not signed by the issuing authority"),
    "unknown_key": N_("it was not signed with any key of the issuing authority"),
    "withdrawn_key": N_(
        "it was signed with a key the issuing authority withdrew because it may have been "
        "misused: ask the authority for a new paper"
    ),
    "unsupported_algorithm": N_("it was not signed the way the issuing authority signs"),
    "malformed": N_("it is damaged or is not a code the issuing authority makes"),
    "tampered": N_("it was signed for a different document from the one on record under this number"),
}


_UNCHECKED = N_("its signature does not check out")


def qr_reason(reason: str) -> str:
    """Why a QR code is not genuine, in words without key ids or codes."""
    return _(_QR_REASONS.get(reason, _UNCHECKED))


def type_occupancy_sentence(compliant: bool, max_compliant_occupants: int) -> str:
    """What a type assessment allows every vehicle of the model, by its confident verdict."""
    if compliant and max_compliant_occupants >= 1:
        if max_compliant_occupants == 1:
            return _("The model is certified for the driver alone: no passengers")
        return _("The model is certified for %(occupancy)s") % {
            "occupancy": occupancy_limit(max_compliant_occupants)
        }
    if max_compliant_occupants <= 0:
        return _("The model is not shown stable even with the driver alone")
    if max_compliant_occupants == 1:
        return _("Vehicles of this model must not carry passengers")
    return _("Vehicles of this model may carry %(occupancy)s, no more") % {
        "occupancy": occupancy_limit(max_compliant_occupants)
    }


def _position(x_m: Decimal, layout: Layout = DELTA) -> str:
    """Where ballast sits, in words: '0.30 m behind the front wheel' (a delta), '0.20 m ahead of the
    front axle' (two front wheels)."""
    places = max(2, -int(x_m.normalize().as_tuple().exponent))
    distance = f"{abs(x_m):.{places}f} m"
    if layout.n_front == 1:
        if x_m == 0:
            return _("over the front wheel")
        if x_m > 0:
            return _("%(distance)s behind the front wheel") % {"distance": distance}
        return _("%(distance)s ahead of the front wheel") % {"distance": distance}
    if x_m == 0:
        return _("over the front axle")
    if x_m > 0:
        return _("%(distance)s behind the front axle") % {"distance": distance}
    return _("%(distance)s ahead of the front axle") % {"distance": distance}


# Where ballast must sit to help, per limit: its own share of the rear axle must be below the limit.
_BALLAST_TOO_FAR = {
    Fraction(2, 3): N_(
        "Ballast %(position)s cannot help: it must sit less than two thirds of the wheelbase behind "
        "the front wheel."
    ),
    Fraction(1, 3): N_(
        "Ballast %(position)s cannot help: it must sit less than one third of the wheelbase behind "
        "the front axle."
    ),
    Fraction(1, 2): N_(
        "Ballast %(position)s cannot help: it must sit less than half the wheelbase behind the front axle."
    ),
}


def _case_left(occupants: int) -> str:
    """A loading case a remedy leaves unfixed: 'the empty vehicle', 'the driver alone'."""
    if occupants == 0:
        return _("the empty vehicle")
    return _("the vehicle with %(occupancy)s") % {"occupancy": occupancy(occupants)}


def _carry_no_more(occupants: int) -> str:
    """The remedy of carrying fewer: 'carry no more than the driver and 2 passengers'."""
    if occupants <= 1:
        return _("carry no more than the driver")
    count = occupants - 1
    return ngettext(
        "carry no more than the driver and one passenger",
        "carry no more than the driver and %(count)s passengers",
        count,
    ) % {"count": count}


def remedy_options(advice: Advice, layout: Layout = DELTA) -> list[str]:
    """Each way to make every case up to the target comply, in words an owner understands."""
    if advice.compliant:
        return []
    options = []
    best = advice.max_compliant_occupants
    if 1 <= best < advice.target_occupants:
        options.append(_carry_no_more(best))
    if advice.ballast_kg is not None:
        options.append(
            _("fit more than %(mass)s kg of ballast %(position)s")
            % {"mass": advice.ballast_kg, "position": _position(advice.ballast_x_m, layout)}
        )
    if advice.seat_shift_m is not None:
        option = _("move the rear bench %(distance)s m forward") % {"distance": advice.seat_shift_m}
        if advice.seat_shift_unfixable:
            left = _case_left(advice.seat_shift_unfixable[0])
            for occupants in advice.seat_shift_unfixable[1:]:
                left = _("%(these)s and %(those)s") % {"these": left, "those": _case_left(occupants)}
            option = _("%(remedy)s, which still leaves %(cases)s non-compliant") % {
                "remedy": option,
                "cases": left,
            }
        options.append(option)
    if advice.tyre_ratio is not None:
        options.append(
            _("fit rear tyres at least %(ratio)s times as stiff in cornering as the front")
            % {"ratio": advice.tyre_ratio}
        )
    return options


def remedies_sentence(advice: Advice, layout: Layout = DELTA) -> str:
    """The remedies in one sentence: 'Carry no more than the driver; or fit more than 54.64 kg of ...'."""
    if advice.compliant:
        return _("Nothing: every loading case up to %(occupancy)s already complies.") % {
            "occupancy": occupancy(advice.target_occupants)
        }
    options = remedy_options(advice, layout)
    sentence = ""
    if options:
        text = options[0]
        for option in options[1:]:
            text = _("%(these)s; or %(those)s") % {"these": text, "those": option}
        sentence = f"{text[:1].upper()}{text[1:]}."
    if not advice.ballast_possible:
        cannot = _(_BALLAST_TOO_FAR[layout.limit]) % {"position": _position(advice.ballast_x_m, layout)}
        sentence = f"{sentence} {cannot}"
    return sentence.strip()


def remedy_applied(advice: Advice, remedy: str, layout: Layout = DELTA) -> str | None:
    """One advised remedy as done: 'after fitting 54.64 kg of ballast 0.30 m behind the front wheel'."""
    if remedy == "ballast" and advice.ballast_kg is not None:
        return _("after fitting %(mass)s kg of ballast %(position)s") % {
            "mass": advice.ballast_kg,
            "position": _position(advice.ballast_x_m, layout),
        }
    if remedy == "seat_shift" and advice.seat_shift_m is not None:
        return _("after moving the rear bench %(distance)s m forward") % {"distance": advice.seat_shift_m}
    return None


def document_headline(kind: str, max_compliant_occupants: int) -> str:
    """What a paper says first: 'CERTIFIED: the driver and up to 2 passengers' or 'NOT CERTIFIED: REFUSAL'."""
    if kind != "compliant":
        return _("NOT CERTIFIED: REFUSAL")
    if max_compliant_occupants <= 1:
        return _("CERTIFIED: the driver alone, no passengers")
    return _("CERTIFIED: %(occupancy)s") % {"occupancy": occupancy_limit(max_compliant_occupants)}


def case_name(occupants: int) -> str:
    """A loading case as a document names it: 'Empty (no occupants)', 'Driver', 'Driver + 2 passengers'."""
    if occupants <= 0:
        return _("Empty (no occupants)")
    if occupants == 1:
        return _("Driver")
    count = occupants - 1
    return ngettext("Driver + %(count)s passenger", "Driver + %(count)s passengers", count) % {"count": count}


_RULES = {
    "lsf<2/3:cumulative-cases:v1": N_("LSF below 2/3 in every loading case (rules v1)"),
    "lsf<1/3:cumulative-cases:v1": N_("LSF below 1/3 in every loading case (tadpole rules v1)"),
    "lsf<1/2:cumulative-cases:v1": N_("LSF below 1/2 in every loading case (quadricycle rules v1)"),
}
# Each wheel's row on an inspection's page (the core's WHEEL_WORDS, capitalised, to be translated).
_WHEEL_ROWS = {
    "front_kg": N_("Front wheel reaction"),
    "left_front_kg": N_("Left front wheel reaction"),
    "right_front_kg": N_("Right front wheel reaction"),
    "left_rear_kg": N_("Left rear wheel reaction"),
    "right_rear_kg": N_("Right rear wheel reaction"),
    "rear_kg": N_("Rear wheel reaction"),
    "overall_kg": N_("Overall weight"),
}


def layout_of(rules_version: str) -> str:
    """The layout a stored rules version was decided under: 'tadpole' for 'lsf<1/3:...'."""
    return layout_of_rules(rules_version).name


def wheel_rows(layout: str = "delta") -> list[tuple[str, str]]:
    """A layout's wheels, front first, each with its name on a page: ('rear_kg', 'Rear wheel reaction')."""
    return [(wheel, _(_WHEEL_ROWS[wheel])) for wheel in LAYOUTS[layout].wheels]


def rear_weight_heading(layout: str = "delta") -> str:
    """Table 4's column of the rear axle's load: 'Weight on rear wheels (kg)', or '... the rear wheel'."""
    return (
        _("Weight on rear wheels (kg)") if LAYOUTS[layout].n_rear > 1 else _("Weight on the rear wheel (kg)")
    )


def variance_note(layout: str = "delta") -> str:
    """What Table 4's variance and verdict mean, with the layout's limit."""
    return _(
        "Variance is %(limit)s minus the LSF: positive is a margin, negative an excess. A case complies "
        "(C) only when its LSF is less than %(limit)s, decided on the exact figures."
    ) % {"limit": LAYOUTS[layout].limit_text}


def chart_caption(layout: str = "delta") -> str:
    """The caption under an inspection's chart, with the layout's limit."""
    return _(
        "Lateral Stability Factor (LSF) of each loading case. Circles marked C are compliant; crosses "
        "marked NC are not. The shaded region above the dashed line at %(limit)s is unstable."
    ) % {"limit": LAYOUTS[layout].limit_text}


def rules_words(rules_version: str) -> str:
    """The rules a verdict was decided under, in words: 'LSF below 2/3 in every loading case (rules v1)'."""
    words = _RULES.get(rules_version)
    return _(words) if words is not None else _("rules %(version)s") % {"version": rules_version}
