"""Columns for elements and attributes. lxml knows an element's line but not its column, and
nothing about attributes; this scans the (already well-formed) text once and maps every start tag
and attribute value to `line:col`, including the column of a character inside a value whose
source spells it as an entity (`&lt;`)."""
from __future__ import annotations

import bisect
import re
from dataclasses import dataclass

from lxml import etree

from .location import Location

_SKIP = re.compile(r"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>|<!.*?>|</[^>]*>", re.DOTALL)
_START = re.compile(r"<([^\s/>!?]+)")
_ATTRIBUTE = re.compile(r"\s*([^\s=/>]+)\s*=\s*(\"[^\"]*\"|'[^']*')")
_REFERENCE = re.compile(r"&(#x[0-9a-fA-F]+|#[0-9]+|[A-Za-z]+);")


@dataclass(frozen=True)
class TagSpans:
    start: int                           # offset of '<'
    attributes: dict[str, tuple[int, int]]  # name as written -> (offset of name, offset of value)


class SourceMap:
    """Offsets of start tags and attributes in document order, turned into locations on demand."""

    def __init__(self, text: str, filename: str) -> None:
        self.text = text
        self.filename = filename
        self._line_starts = [0] + [m.end() for m in re.finditer(r"\n", text)]
        self._tags = _scan(text)
        self._by_element: dict[etree._Element, TagSpans] = {}

    def bind(self, root: etree._Element) -> None:
        """Pair lxml's elements (document order) with the scanned start tags."""
        for element, spans in zip(root.iter(etree.Element), self._tags):
            self._by_element[element] = spans

    def location(self, offset: int) -> Location:
        line = bisect.bisect_right(self._line_starts, offset) - 1
        return Location(self.filename, line + 1, offset - self._line_starts[line] + 1)

    def element(self, element: etree._Element) -> Location:
        spans = self._by_element.get(element)
        if spans is None:
            return Location(self.filename, element.sourceline or 1, 1)
        return self.location(spans.start)

    def attribute(self, element: etree._Element, name: str) -> Location:
        """Where the attribute's name starts (the element's start when it is missing)."""
        spans = self._spans(element, name)
        return self.location(spans[0]) if spans else self.element(element)

    def value(self, element: etree._Element, name: str, index: int = 0) -> Location:
        """Where character `index` of the attribute's decoded value sits in the file."""
        spans = self._spans(element, name)
        if not spans:
            return self.element(element)
        return self.location(_raw_offset(self.text, spans[1] + 1, index))

    def _spans(self, element: etree._Element, name: str) -> tuple[int, int] | None:
        spans = self._by_element.get(element)
        if spans is None:
            return None
        if name in spans.attributes:
            return spans.attributes[name]
        local = name.rsplit("}", 1)[-1]
        for written, found in spans.attributes.items():
            if written.rsplit(":", 1)[-1] == local:
                return found
        return None


def _scan(text: str) -> list[TagSpans]:
    tags: list[TagSpans] = []
    position = 0
    while True:
        index = text.find("<", position)
        if index < 0:
            return tags
        skipped = _SKIP.match(text, index)
        if skipped:
            position = skipped.end()
            continue
        start = _START.match(text, index)
        if not start:
            position = index + 1
            continue
        attributes: dict[str, tuple[int, int]] = {}
        position = start.end()
        while True:
            attribute = _ATTRIBUTE.match(text, position)
            if not attribute:
                break
            attributes[attribute.group(1)] = (attribute.start(1), attribute.start(2))
            position = attribute.end()
        tags.append(TagSpans(index, attributes))


def _raw_offset(text: str, value_start: int, index: int) -> int:
    """Offset in `text` of decoded character `index` of the value starting at `value_start`."""
    position = value_start
    for _ in range(index):
        if text[position] == "&":
            reference = _REFERENCE.match(text, position)
            position = reference.end() if reference else position + 1
        else:
            position += 1
    return position
