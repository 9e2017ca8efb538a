"""The syntax tree of a condition. Plain frozen data: the parser builds it, the type checker
annotates a copy, the compiler turns it into closures, the analyser reasons over it."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Union


@dataclass(frozen=True)
class Literal:
    value: object          # Fraction, str or bool; numbers exactly as written (before units)
    unit: str | None       # "s", "ms", "min", "m", "cm", "deg" or None
    offset: int
    end: int


@dataclass(frozen=True)
class Name:
    name: str              # a dotted percept name or "time_in_state"
    offset: int
    end: int


@dataclass(frozen=True)
class Compare:
    op: str                # one of < <= > >= == !=
    left: "Operand"
    right: "Operand"
    offset: int
    end: int


@dataclass(frozen=True)
class Not:
    operand: "Node"
    offset: int
    end: int


@dataclass(frozen=True)
class And:
    operands: tuple["Node", ...]
    offset: int
    end: int


@dataclass(frozen=True)
class Or:
    operands: tuple["Node", ...]
    offset: int
    end: int


Operand = Union[Literal, Name]
Node = Union[Literal, Name, Compare, Not, And, Or]


def unparse(node: Node) -> str:
    """Canonical text of a tree; parsing it again gives the same tree (up to offsets)."""
    if isinstance(node, Literal):
        return _literal_text(node)
    if isinstance(node, Name):
        return node.name
    if isinstance(node, Compare):
        return f"{unparse(node.left)} {node.op} {unparse(node.right)}"
    if isinstance(node, Not):
        return f"not {_wrapped(node.operand)}"
    joiner = " and " if isinstance(node, And) else " or "
    return joiner.join(_wrapped(item) for item in node.operands)


def _wrapped(node: Node) -> str:
    text = unparse(node)
    return f"({text})" if isinstance(node, (And, Or, Compare)) else text


def _literal_text(node: Literal) -> str:
    if isinstance(node.value, bool):
        return "true" if node.value else "false"
    if isinstance(node.value, str):
        escaped = node.value.replace("\\", "\\\\").replace('"', '\\"')
        return f'"{escaped}"'
    from .units import decimal_text
    number = decimal_text(node.value)
    return f"{number}{node.unit}" if node.unit else number
