"""Per-body reading and identification flags of ``impactpred predict``.

Every flag that says how an FRF file is read or identified (``--quantity``, ``--conjugate``,
``--index``, ``--window-decay``, ``--fmin``, ...) applies to every body given as a file; the
same flag with ``1`` or ``2`` appended (``--conjugate2``, ``--window-decay1 5.2``) applies to
that body only, over the common one. Two files from different sources (one stored with the
other sign convention, one measured with a window its file does not state, two records of
one UFF file) need that. Where both bodies are files, a message about one body that names
such flags says how to give them to that body alone (:func:`for_body`).
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

from modalid._cli import add_fit_options, add_read_options

__all__ = ["BODY_FLAGS_HELP", "add_body_flags", "body_args", "for_body", "identification_flags",
           "in_body_flags", "is_file_body"]

#: the help line that says the per-body flags exist (they are not listed one by one)
BODY_FLAGS_HELP = ("these flags and the identification flags below apply to every body read "
                   "from a file; append 1 or 2 to one to apply it to that body only, over "
                   "the common one (--conjugate2, --quantity1 accelerance, --index2 1, "
                   "--window-decay2 5.2, --fmin1 20; --no-conjugate2, --no-negate1 turn a "
                   "common switch off for one body)")

_BODIES = (1, 2)


def _actions():
    """The argparse actions of every reading and identification flag."""
    parser = argparse.ArgumentParser(add_help=False)
    add_fit_options(parser, method_flags=("--fit-method",))
    add_read_options(parser)
    return [action for action in parser._actions if action.option_strings]


def identification_flags(*, per_body=True) -> dict:
    """Destination -> flag of every reading and identification flag, and (``per_body``)
    of its per-body forms (``conjugate_2`` -> ``--conjugate2``)."""
    flags = {action.dest: action.option_strings[0] for action in _actions()}
    if per_body:
        flags.update({f"{dest}_{i}": f"{flag}{i}" for dest, flag in list(flags.items())
                      for i in _BODIES})
    return flags


def add_body_flags(parser) -> None:
    """Add ``--FLAG1``/``--FLAG2`` (destination ``DEST_1``/``DEST_2``, default None,
    hidden from the listing: ``BODY_FLAGS_HELP`` says so) for every reading and
    identification flag."""
    for action in _actions():
        for i in _BODIES:
            flag, dest = f"{action.option_strings[0]}{i}", f"{action.dest}_{i}"
            if action.nargs == 0:                       # a switch (--conjugate)
                parser.add_argument(flag, dest=dest, action="store_true", default=None,
                                    help=argparse.SUPPRESS)
                if not flag.startswith("--not-"):       # off for one body: --no-conjugate2
                    parser.add_argument(f"--no-{flag[2:]}", dest=dest, action="store_false",
                                        default=None, help=argparse.SUPPRESS)
            else:
                parser.add_argument(flag, dest=dest, type=action.type, choices=action.choices,
                                    metavar=action.metavar, default=None,
                                    help=argparse.SUPPRESS)


def body_args(args, body: int) -> argparse.Namespace:
    """``args`` as body ``body`` (1 or 2) sees them: each reading and identification
    flag's per-body value where it was given, else the common one."""
    values = vars(args).copy()
    for dest in identification_flags(per_body=False):
        own = values.get(f"{dest}_{body}")
        if own is not None:
            values[dest] = own
    own_point, own_not = values.get(f"driving_point_{body}"), values.get(
        f"not_driving_point_{body}")
    if own_point is not None and not own_not:
        values["not_driving_point"] = False     # --driving-point2 yes over --not-driving-point
    if own_not and own_point is None:
        values["driving_point"] = None          # --not-driving-point2 over --driving-point yes
    return argparse.Namespace(**values)


def in_body_flags(message: str, args, body: int) -> str:
    """``message``, raised while building body ``body``'s reading or identification
    options, in the flags given for that body: where any was given for it alone, each
    such flag the message names in its per-body form (``--freq-start2``) and the message
    led by ``body N:`` (so that :func:`for_body` adds how to give a missing one to it)."""
    flags = identification_flags(per_body=False)
    own = [flag for dest, flag in flags.items()
           if getattr(args, f"{dest}_{body}", None) is not None]
    if not own:
        return message
    for flag in own:
        message = re.sub(rf"(?<![\w-]){re.escape(flag)}(?![\w-])", f"{flag}{body}", message)
    return message if re.match(r"body [12]\b", message) else f"body {body}: {message}"


def is_file_body(spec) -> bool:
    """Whether the body ``spec`` is an FRF file to read and identify (not a spec string,
    not a saved ``.json`` fit or model)."""
    from ._specs import is_spec

    return not is_spec(spec) and Path(spec).suffix.lower() != ".json"


def for_body(message: str, args) -> str:
    """``message`` (in flags already) about the body it starts with (``body 2: ...``): the
    flags given for that body alone in their per-body form (``--quantity2``); where both
    bodies are files and it names common reading or identification flags, that those
    apply to both files and how to give one to that body alone (``--conjugate2``)."""
    match = re.match(r"body ([12])\b", message)
    if match is None:
        return message
    message = in_body_flags(message, args, int(match.group(1)))   # --quantity2, if given
    if not all(is_file_body(s) for s in (args.body1, args.body2)):
        return message
    named = [flag for flag in identification_flags(per_body=False).values()
             if re.search(rf"(?<![\w-]){re.escape(flag)}(?![\w-])", message)]
    if not named:
        return message
    verb = "applies" if len(named) == 1 else "apply"
    return (f"{message}; with two FRF files {', '.join(named)} {verb} to both: add 1 or 2 "
            f"for one alone ({named[0]}{match.group(1)})")
