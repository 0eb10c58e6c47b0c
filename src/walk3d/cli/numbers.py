"""Numeric options read as the user sees them: Typer reads ``--mass 6_8`` as 68 and
``--speed 1.2٣`` as 1.23, as Python's ``float()`` and ``int()`` do. :func:`plain_numbers`
refuses, before any command runs, a numeric option's value that is not a plain decimal
(spaces around it are allowed, as in the what-if and descriptor options)."""

from __future__ import annotations

import math
import re
import types
from collections.abc import Iterator
from typing import Any, Union, get_args, get_origin

from walk3d.decimals import decimal

_INTEGER = re.compile(r"[+-]?\d+", re.ASCII)
_WORDS = re.compile(r"[+-]?(nan|inf|infinity)", re.ASCII | re.IGNORECASE)
"""What ``float()`` reads as written: the command's own check refuses it, naming its range."""


def _kind(param: Any) -> type | None:
    """``int`` or ``float`` for a numeric option (also optional), else None."""
    annotation = getattr(getattr(param, "type_descriptor", None), "annotation", None)
    if get_origin(annotation) in (Union, types.UnionType):
        found = [a for a in get_args(annotation) if a is not type(None)]
        annotation = found[0] if len(found) == 1 else None
    if get_origin(annotation) is list:  # an option given more than once
        annotation = get_args(annotation)[0]
    return annotation if annotation in (int, float) else None


def _numeric_options(command: Any, args: list[str]) -> tuple[dict[str, type], list[str]]:
    """The numeric options of the (sub)command that ``args`` name, by option string, and the
    args that follow the command's name."""
    while hasattr(command, "commands") and args and args[0] in command.commands:
        command, args = command.commands[args[0]], args[1:]
    options = {}
    for param in getattr(command, "params", ()):
        kind = _kind(param)
        if kind is not None:
            options.update((opt, kind) for opt in param.opts)
    return options, args


def _values(options: dict[str, type], args: list[str]) -> Iterator[tuple[str, type, str]]:
    i = 0
    while i < len(args):
        token = args[i]
        if token == "--":
            return
        name, eq, value = token.partition("=")
        if name in options and eq:
            yield name, options[name], value
        elif token in options and i + 1 < len(args):
            yield token, options[token], args[i + 1]
            i += 1
        i += 1


def plain_numbers(command: Any, args: list[str]) -> str | None:
    """The error line for the first numeric option in ``args`` whose value is not a plain
    decimal (an integer for an integer option), or None."""
    options, rest = _numeric_options(command, args)
    for name, kind, value in _values(options, rest):
        if kind is int and not _INTEGER.fullmatch(value.strip()):
            return f"{name} takes an integer, got {value!r}"
        if kind is float and _WORDS.fullmatch(value):
            continue
        if kind is float and math.isnan(decimal(value)):
            return f"{name} takes a finite decimal number, got {value!r}"
    return None
