"""The RelaxNG schema of graph.xml, shipped with the package and validated with lxml.

The reader reports structural mistakes itself, with columns and did-you-mean hints; the schema is
the formal description and the backstop for anything the reader does not word better."""
from __future__ import annotations

from functools import lru_cache
from pathlib import Path

from lxml import etree

from .xmlsafe import safe_parser

SCHEMA_FILE = Path(__file__).resolve().parent.parent / "schema" / "graph.rng"


@lru_cache(maxsize=1)
def graph_schema() -> etree.RelaxNG:
    return etree.RelaxNG(etree.parse(str(SCHEMA_FILE), safe_parser()))


def schema_problems(tree: etree._ElementTree) -> list[tuple[int, str]]:
    """(line, message) for each schema violation; empty when the document is valid."""
    schema = graph_schema()
    if schema.validate(tree):
        return []
    return [(entry.line or 1, entry.message) for entry in schema.error_log]
