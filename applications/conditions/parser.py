"""Recursive-descent parser of the condition language. The grammar, all of it:

    condition  := or_expr END
    or_expr    := and_expr ("or" and_expr)*
    and_expr   := not_expr ("and" not_expr)*
    not_expr   := "not" not_expr | comparison
    comparison := primary (("<"|"<="|">"|">="|"=="|"!=") primary)?
    primary    := NUMBER UNIT? | STRING | "true" | "false" | NAME | "(" or_expr ")"

No calls, no attribute access beyond dotted names, no indexing: there is nothing to escape into.
"""
from __future__ import annotations

import math

from ..exceptions import ConditionError
from .lexer import Token, tokenize
from .nodes import And, Compare, Literal, Name, Node, Not, Or
from .units import UNITS

MAX_DEPTH = 100   # nesting deeper than this is an error, not a RecursionError


def parse(text: str) -> Node:
    """The syntax tree of `text`; ConditionError with the offset of the first problem."""
    if not text.strip():
        raise ConditionError("empty condition: write e.g. time_in_state > 30s", 0, text)
    return _Parser(text).parse()


class _Parser:
    def __init__(self, text: str) -> None:
        self.text = text
        self.tokens = tokenize(text)
        self.index = 0
        self.depth = 0

    @property
    def current(self) -> Token:
        return self.tokens[self.index]

    def advance(self) -> Token:
        token = self.tokens[self.index]
        self.index += 1
        return token

    def fail(self, message: str, token: Token | None = None) -> ConditionError:
        token = token or self.current
        return ConditionError(message, token.offset, self.text)

    def parse(self) -> Node:
        node = self.or_expr()
        if self.current.kind != "END":
            raise self.fail(self._unexpected_after_expression())
        return node

    def _unexpected_after_expression(self) -> str:
        token = self.current
        if token.kind == "RPAREN":
            return "')' without a matching '('"
        if token.kind == "OP":
            return ("comparisons cannot be chained: write 'a < x and x < b' instead of "
                    "'a < x < b'")
        return f"expected 'and', 'or' or the end of the condition, found {_describe(token)}"

    def or_expr(self) -> Node:
        return self._joined("or", self.and_expr, Or)

    def and_expr(self) -> Node:
        return self._joined("and", self.not_expr, And)

    def _joined(self, keyword: str, operand, node_type) -> Node:
        first = operand()
        operands = [first]
        while self.current.kind == "KEYWORD" and self.current.text == keyword:
            self.advance()
            operands.append(operand())
        if len(operands) == 1:
            return first
        return node_type(tuple(operands), first.offset, operands[-1].end)

    def not_expr(self) -> Node:
        token = self.current
        if token.kind == "KEYWORD" and token.text == "not":
            self.advance()
            self._enter()
            operand = self.not_expr()
            self.depth -= 1
            return Not(operand, token.offset, operand.end)
        return self.comparison()

    def comparison(self) -> Node:
        left = self.primary()
        if self.current.kind != "OP":
            return left
        op = self.advance().text
        right = self.primary()
        return Compare(op, left, right, left.offset, right.end)

    def primary(self) -> Node:
        token = self.current
        if token.kind == "NUMBER":
            return self.number()
        if token.kind == "STRING":
            self.advance()
            return Literal(token.text, None, token.offset, token.end)
        if token.kind == "KEYWORD" and token.text in ("true", "false"):
            self.advance()
            return Literal(token.text == "true", None, token.offset, token.end)
        if token.kind == "NAME":
            return self.name()
        if token.kind == "LPAREN":
            return self.parenthesised()
        raise self.fail(f"expected a percept name, a number, a string, true/false or '(', "
                        f"found {_describe(token)}")

    def number(self) -> Literal:
        token = self.advance()
        value = float(token.text)
        if not math.isfinite(value):
            raise self.fail(f"number {token.text} is too large", token)
        unit_token = self.current
        if unit_token.kind == "NAME" and unit_token.offset == token.end:
            if unit_token.text not in UNITS:
                raise self.fail(f"unknown unit '{unit_token.text}': use one of "
                                f"{', '.join(UNITS)}", unit_token)
            self.advance()
            return Literal(value, unit_token.text, token.offset, unit_token.end)
        if unit_token.kind == "NAME" and unit_token.text in UNITS:
            raise self.fail(f"write the unit right after the number: "
                            f"{token.text}{unit_token.text}", unit_token)
        return Literal(value, None, token.offset, token.end)

    def name(self) -> Name:
        token = self.advance()
        following = self.current
        if following.kind == "LPAREN":
            raise self.fail(f"'{token.text}(' looks like a call: conditions cannot call "
                            "anything", following)
        if following.kind in ("NAME", "NUMBER", "STRING"):
            raise self.fail(f"expected a comparison, 'and', 'or' or ')' after '{token.text}', "
                            f"found {_describe(following)}", following)
        return Name(token.text, token.offset, token.end)

    def parenthesised(self) -> Node:
        opening = self.advance()
        self._enter()
        if self.current.kind == "RPAREN":
            raise self.fail("empty parentheses: put a condition inside")
        node = self.or_expr()
        self.depth -= 1
        if self.current.kind != "RPAREN":
            raise self.fail(f"'(' at column {opening.offset + 1} is not closed: add ')'"
                            if self.current.kind == "END" else
                            f"expected ')', found {_describe(self.current)}")
        self.advance()
        return node

    def _enter(self) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise self.fail(f"nested more than {MAX_DEPTH} levels deep: simplify the condition")


def _describe(token: Token) -> str:
    if token.kind == "END":
        return "the end of the condition"
    if token.kind == "STRING":
        return f"the string {token.text!r}"
    return f"'{token.text}'"
