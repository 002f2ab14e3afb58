"""Whether two figure files are the same figure: PNG byte for byte, PDF as structure.

A PDF's bytes hold every coordinate written to ten decimals, and a coordinate that lands next to
a rounding boundary flips its last decimal on a processor whose arithmetic differs in the last
bit (glamas computes what it can portably, :mod:`glamas.portable`, but not every library it draws
through). So a PDF is compared as what it says: its objects in order, each stream decompressed and
read as PDF tokens, the same names, operators, strings and integers in the same order, and every
real number within :data:`TOLERANCE` points of its twin, some ten thousand times below the width
of the finest line drawn. Stream lengths and the cross-reference table, which only say where the
bytes lie, are not compared. A PNG's pixels are rasterized from the same coordinates at 150 dots
per inch, and are compared byte for byte.

:func:`compare` says which of three things holds: the same bytes; the same figure within the
tolerance (``make verify`` and the tests accept it, and say so); or different, with where.
"""

import re
import zlib
from typing import NamedTuple

TOLERANCE = 1e-6
"""The largest difference between two real numbers of twin PDFs that is not a difference of the
figure, in points (1/72 inch): 1e-6 pt is some 4e-10 mm."""

_XREF = re.compile(rb"\nxref\n0 (\d+)\n")
_LENGTH_REF = re.compile(rb"/Length (\d+) 0 R")
_HEADER = re.compile(rb"\s*(\d+) (\d+) obj\b")
_TOKEN = re.compile(rb"""
    (?P<space>[\x00\t\n\x0c\r ]+)
  | (?P<comment>%[^\r\n]*)
  | (?P<hex><[0-9A-Fa-f\s]*>)
  | (?P<dict><<|>>)
  | (?P<name>/[^\x00\t\n\x0c\r /\[\]()<>{}%]*)
  | (?P<number>[+-]?(?:\d+\.\d*|\.\d+|\d+))(?![^\x00\t\n\x0c\r /\[\]()<>{}%])
  | (?P<delimiter>[\[\]{}])
  | (?P<word>[^\x00\t\n\x0c\r /\[\]()<>{}%]+)
  | (?P<other>[\s\S])
""", re.X)
_BINARY_STREAM = re.compile(rb"/Subtype\s*/Image|/Length1|/FontFile")


class _Unreadable(Exception):
    """The bytes are not a PDF of the form matplotlib writes."""


class Comparison(NamedTuple):
    """What :func:`compare` found."""

    same_bytes: bool
    """The two files are identical."""
    equal: bool
    """The same figure: identical, or PDFs whose every real number is within :data:`TOLERANCE`."""
    detail: str
    """Where they differ (not ``equal``), or how far apart their numbers are (``equal`` but not
    ``same_bytes``); empty for identical files."""


def compare(ours: bytes, theirs: bytes, suffix: str, tolerance: float = TOLERANCE) -> Comparison:
    """Whether ``ours`` and ``theirs``, two figure files of type ``suffix`` ('.png' or '.pdf'),
    are the same figure."""
    if ours == theirs:
        return Comparison(True, True, "")
    if suffix != ".pdf":
        return Comparison(False, False, "its bytes differ")
    try:
        a, b = _objects(ours), _objects(theirs)
    except (_Unreadable, ValueError, zlib.error) as error:  # ValueError: a damaged number in its tables
        return Comparison(False, False, f"it is not a PDF glamas can read ({error})")
    if len(a) != len(b):
        return Comparison(False, False, f"it has {len(a)} PDF objects where the committed figure has {len(b)}")
    largest = 0.0
    for k, (x, y) in enumerate(zip(a, b)):
        found = _token_difference(x, y, tolerance)
        if isinstance(found, str):
            return Comparison(False, False, f"PDF object {k + 1}: {found}")
        largest = max(largest, found)
    return Comparison(False, True, f"numbers within {largest:.1g} pt of the committed figure's (tolerance {tolerance:g})")


def _objects(pdf: bytes) -> list[list[tuple]]:
    """The PDF's objects in the order of its cross-reference table, each as its tokens: the
    dictionary's, then the decompressed stream's (a font or an image as one token of its bytes);
    the stream lengths left out."""
    found = list(_XREF.finditer(pdf))
    if not found:
        raise _Unreadable("no cross-reference table")
    xref = found[-1]
    count = int(xref.group(1))
    table = pdf[xref.end(): xref.end() + 20 * count]
    offsets = sorted(int(table[20 * i: 20 * i + 10]) for i in range(count) if table[20 * i + 17: 20 * i + 18] == b"n")
    bodies = [pdf[start: end] for start, end in zip(offsets, offsets[1:] + [xref.start() + 1])]
    lengths = {int(number) for body in bodies for number in _LENGTH_REF.findall(body.split(b"stream", 1)[0])}
    objects = []
    for body in bodies:
        header = _HEADER.match(body)
        if header is None:
            raise _Unreadable("an object without its header")
        if int(header.group(1)) in lengths:
            continue
        objects.append(_object_tokens(body[header.end():].rsplit(b"endobj", 1)[0]))
    return objects


def _object_tokens(body: bytes) -> list[tuple]:
    head, streamed, rest = body.partition(b"stream")
    if not streamed:
        return _tokens(body)
    tokens = _tokens(re.sub(rb"/Length \d+( 0 R)?", b"", head))
    data = rest[2:] if rest.startswith(b"\r\n") else rest[1:]
    data = data.rsplit(b"endstream", 1)[0]
    if b"/FlateDecode" in head:
        data = zlib.decompressobj().decompress(data)
    if _BINARY_STREAM.search(head):
        return tokens + [("bytes", data)]
    return tokens + [("stream", b"")] + _tokens(data)


def _tokens(text: bytes) -> list[tuple]:
    """PDF tokens of ``text`` as (kind, value); literal strings read with their escapes and nested
    parentheses, whitespace and comments dropped."""
    tokens, at = [], 0
    while at < len(text):
        if text[at:at + 1] == b"(":
            end = _string_end(text, at)
            tokens.append(("string", text[at:end]))
            at = end
            continue
        match = _TOKEN.match(text, at)
        kind = match.lastgroup
        if kind not in ("space", "comment"):
            tokens.append((kind, match.group()))
        at = match.end()
    return tokens


def _string_end(text: bytes, start: int) -> int:
    """The index after the literal string that opens at ``start``."""
    depth, at = 0, start
    while at < len(text):
        char = text[at:at + 1]
        if char == b"\\":
            at += 2
            continue
        depth += {b"(": 1, b")": -1}.get(char, 0)
        at += 1
        if depth == 0:
            return at
    raise _Unreadable("a string that does not end")


def _token_difference(ours: list, theirs: list, tolerance: float):
    """The largest difference between the real numbers of two token lists that agree in
    everything else and within ``tolerance``; else a description of the first difference."""
    if len(ours) != len(theirs):
        return f"{len(ours)} tokens where the committed figure has {len(theirs)}"
    largest = 0.0
    for k, ((kind, value), (their_kind, their_value)) in enumerate(zip(ours, theirs)):
        if value == their_value and kind == their_kind:
            continue
        if kind == their_kind == "number" and (b"." in value or b"." in their_value):
            gap = abs(float(value) - float(their_value))
            if gap <= tolerance:
                largest = max(largest, gap)
                continue
        return f"token {k + 1}: {_shown(value)} where the committed figure has {_shown(their_value)}"
    return largest


def _shown(value: bytes) -> str:
    return repr(value[:40].decode("latin-1")) + ("..." if len(value) > 40 else "")
