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

import re

from ..exceptions import ConditionError
from ..graph.diagnostics import did_you_mean
from .hints import KEYWORDS, unit_alias, unit_on_name, unit_suggestion, word_operator
from .lexer import Token, scan
from .nodes import And, Compare, Literal, Name, Node, Not, Or
from .units import UNITS, NumberError, exact

_WORD = re.compile(r"[A-Za-z]+(?:[ \t]+[A-Za-z]+){0,2}")   # up to three words
MAX_DEPTH = 100   # nesting deeper than this is an error, not a RecursionError


def parse(text: str) -> Node:
    """The syntax tree of `text`; ConditionError with the offset of the first problem."""
    if not text.strip():
        raise ConditionError("empty condition: write e.g. time_in_state > 30s", 0, text)
    return _Parser(text).parse()


class _Parser:
    def __init__(self, text: str) -> None:
        self.text = text
        self.tokens = scan(text)
        self.index = 0
        self.depth = 0
        self.last_name: str | None = None      # the percept compared last, for hints

    @property
    def peek(self) -> Token:
        """The current token, even an ERROR one (to look for a better hint before it)."""
        return self.tokens[self.index]

    @property
    def current(self) -> Token:
        token = self.tokens[self.index]
        if token.kind == "ERROR":          # a stray character, reached in reading order
            raise ConditionError(token.text, token.offset, self.text)
        return token

    def advance(self) -> Token:
        token = self.current
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
            return "')' without a matching '(': delete it, or add the '(' where the group starts"
        if token.kind == "OP":
            return ("comparisons cannot be chained: write 'a < x and x < b' instead of "
                    "'a < x < b'")
        hint = self.word_operator_hint()
        if hint:
            return hint
        if token.kind == "LPAREN":
            return f"expected 'and' or 'or' before '(', found {_describe(token)}"
        return f"expected 'and', 'or' or the end of the condition, found {_describe(token)}"

    def word_operator_hint(self) -> str | None:
        """`is`, `is not`, `equals`, `not in`… where an operator belongs: what to write."""
        words = []
        for token in self.tokens[self.index:]:
            if token.kind == "ERROR":          # e.g. `IS NOT`: NOT is a keyword in capitals
                word = _WORD.match(self.text, token.offset)
                if word and word.group().split()[0].lower() in KEYWORDS:
                    words.extend(word.group().split())
            if token.kind not in ("NAME", "KEYWORD"):
                break
            words.append(token.text)
        found = word_operator(words)
        return found[1] if found else None

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
        if self.peek.kind in ("NAME", "KEYWORD", "ERROR"):
            hint = self.word_operator_hint()
            if hint:
                raise self.fail(hint)
        if self.current.kind != "OP":
            return left
        op = self.advance().text
        right = self.primary()
        return Compare(op, left, right, left.offset, right.end)

    def primary(self) -> Node:
        token = self.current
        if token.kind == "KEYWORD" and token.text in ("and", "or"):
            raise self.fail(self._missing_operand(token))
        if token.kind == "OP" and self.last_name is not None and self.index and \
                self.tokens[self.index - 1].kind == "KEYWORD":
            raise self.fail(f"'{token.text}' needs something on its left: repeat the percept, "
                            f"e.g. {self.last_name} {token.text} …")
        before = self.tokens[self.index - 1] if self.index else None
        if token.kind == "END" and before is not None and before.kind == "KEYWORD":
            raise self.fail(self._missing_operand(before))
        if (token.kind in ("END", "RPAREN") or token.text in ("and", "or", "not")) and \
                before is not None and before.kind == "OP":
            raise self.fail(f"'{before.text}' needs a value on its right, e.g. "
                            f"{self.last_name or 'user.distance'} {before.text} "
                            f"{'true' if before.text in ('==', '!=') else '1'}")
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

    def _missing_operand(self, keyword: Token) -> str:
        before = self.tokens[self.index - 1] if self.index else None
        if self.current.kind == "END" and keyword is before:
            return (f"the condition ends after '{keyword.text}': add what must "
                    f"{'also ' if keyword.text == 'and' else ''}hold, or delete "
                    f"'{keyword.text}'")
        if before is None or before.kind in ("LPAREN", "KEYWORD"):
            where = "at the start" if before is None else f"after '{before.text}'"
            return (f"'{keyword.text}' {where} has nothing to join: put a condition on each "
                    f"side, e.g. user.present {keyword.text} time_in_state > 5s")
        return f"expected a value after '{before.text}', found '{keyword.text}'"

    def number(self) -> Literal:
        token = self.advance()
        try:
            value = exact(token.text)
        except NumberError as problem:
            raise self.fail(str(problem), token) from None
        unit_token = self.current
        if unit_token.kind == "NAME" and unit_token.offset == token.end:
            if unit_token.text not in UNITS:
                raise self.fail(_unit_message(token.text, unit_token.text), unit_token)
            self.advance()
            return Literal(value, unit_token.text, token.offset, unit_token.end)
        if unit_token.kind == "NAME" and unit_token.text in UNITS:
            raise self.fail(f"write the unit right after the number: "
                            f"{token.text}{unit_token.text}", unit_token)
        if unit_token.kind == "NAME" and unit_alias(unit_token.text):
            raise self.fail(f"unknown unit '{unit_token.text}', and a unit goes right after "
                            f"the number: write {unit_suggestion(token.text, unit_token.text)}",
                            unit_token)
        if unit_token.kind == "NUMBER" and unit_token.offset == token.end:
            raise self.fail(f"'{token.text}{unit_token.text}' is not a number: a number has at "
                            "most one decimal point and a sign only in front, e.g. -1.5",
                            unit_token)
        if unit_token.kind == "NUMBER":
            raise self.fail(f"two numbers in a row: write one number without spaces, e.g. "
                            f"{token.text}{unit_token.text.lstrip('-')}", unit_token)
        return Literal(value, None, token.offset, token.end)

    def name(self) -> Name:
        token = self.advance()
        if self.peek.kind == "ERROR":
            hint = self.word_operator_hint()
            if hint:
                raise self.fail(hint, self.peek)
        following = self.current
        if following.kind == "LPAREN":
            unit = self.tokens[self.index + 1]
            if unit.kind == "NAME" and self.tokens[self.index + 2].kind == "RPAREN" and \
                    (unit.text in UNITS or unit_alias(unit.text)):
                raise self.fail(unit_on_name(token.text, unit.text), following)
            raise self.fail(f"'{token.text}(' looks like a call: conditions cannot call "
                            "anything; compare a percept with a value, e.g. user.distance < 1m",
                            following)
        if following.kind in ("NAME", "KEYWORD") and following.text != "and" and \
                following.text != "or":
            hint = self.word_operator_hint()
            if hint:
                raise self.fail(hint, following)
            if following.text in UNITS or unit_alias(following.text):
                raise self.fail(unit_on_name(token.text, following.text), following)
        if following.kind in ("NAME", "NUMBER", "STRING", "KEYWORD") and \
                following.text not in ("and", "or"):
            raise self.fail(f"expected a comparison, 'and', 'or' or ')' after '{token.text}', "
                            f"found {_describe(following)}", following)
        self.last_name = token.text
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
                            f"expected ')', 'and' or 'or', found {_describe(self.current)}")
        self.advance()
        return node

    def _enter(self) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise self.fail(f"nested more than {MAX_DEPTH} levels deep: simplify the condition")


def _unit_message(number: str, word: str) -> str:
    suggestion = unit_suggestion(number, word)
    if suggestion:
        return f"unknown unit '{word}': write {suggestion}"
    return f"unknown unit '{word}'{did_you_mean(word, UNITS)}: use one of {', '.join(UNITS)}"


def _describe(token: Token) -> str:
    if token.kind == "END":
        return "the end of the condition"
    if token.kind == "STRING":
        return f"the string {token.text!r}"
    return f"'{token.text}'"
