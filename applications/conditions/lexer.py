"""Tokens of the condition language: the first gate of the closed grammar.

Only what the grammar needs is a token; anything else (`.` after a string, `[`, `:`, `_` names,
`{`, backslashes, lambdas' colons…) stops here with the column, so no user text ever reaches Python.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

from ..exceptions import ConditionError

KEYWORDS = frozenset({"and", "or", "not", "true", "false"})
COMPARISONS = ("<=", ">=", "==", "!=", "<", ">")

# What people from other languages type, and what to write instead.
_HINTS = {"&&": "and", "||": "or", "!": "not", "=": "==", "<>": "!=", "&": "and", "|": "or"}


@dataclass(frozen=True)
class Token:
    kind: str      # NUMBER, STRING, NAME, KEYWORD, OP, LPAREN, RPAREN, END
    text: str      # the source text of the token (the decoded value for STRING)
    offset: int    # 0-based index into the condition text
    end: int       # index just past the token


_NUMBER = re.compile(r"(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?")
_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*(?:\.[A-Za-z][A-Za-z0-9_]*)*")
_SPACE = re.compile(r"\s+")


def tokenize(text: str) -> list[Token]:
    """The tokens of `text`, ending with an END token; ConditionError on the first stray character."""
    tokens: list[Token] = []
    position = 0
    while True:
        match = _SPACE.match(text, position)
        if match:
            position = match.end()
        if position >= len(text):
            tokens.append(Token("END", "", position, position))
            return tokens
        token = _next_token(text, position)
        tokens.append(token)
        position = token.end


def _next_token(text: str, position: int) -> Token:
    char = text[position]
    if char.isdigit() or (char == "." and text[position + 1:position + 2].isdigit()):
        match = _NUMBER.match(text, position)
        return Token("NUMBER", match.group(), position, match.end())
    if char.isalpha():
        return _name_token(text, position)
    if char in "\"'":
        return _string_token(text, position)
    if char == "(":
        return Token("LPAREN", char, position, position + 1)
    if char == ")":
        return Token("RPAREN", char, position, position + 1)
    for op in COMPARISONS:
        if text.startswith(op, position):
            return Token("OP", op, position, position + len(op))
    raise ConditionError(_stray_message(text, position), position, text)


def _name_token(text: str, position: int) -> Token:
    match = _NAME.match(text, position)
    end = match.end()
    if end < len(text) and (text[end] == "_" or text[end] == "."):
        raise ConditionError(
            f"'{text[end]}' cannot follow '{match.group()}' here: names are letters, digits and "
            "underscores, parts joined by single dots, e.g. user.distance", end, text)
    word = match.group()
    kind = "KEYWORD" if word in KEYWORDS else "NAME"
    return Token(kind, word, position, end)


def _string_token(text: str, position: int) -> Token:
    quote = text[position]
    chars: list[str] = []
    index = position + 1
    while index < len(text):
        char = text[index]
        if char == quote:
            return Token("STRING", "".join(chars), position, index + 1)
        if char == "\\":
            following = text[index + 1:index + 2]
            if following not in (quote, "\\"):
                raise ConditionError(f"only \\{quote} and \\\\ may be escaped in a string",
                                     index, text)
            chars.append(following)
            index += 2
            continue
        chars.append(char)
        index += 1
    raise ConditionError(f"string not closed: add the closing {quote}", position, text)


def _stray_message(text: str, position: int) -> str:
    for typed, meant in sorted(_HINTS.items(), key=lambda item: -len(item[0])):
        if text.startswith(typed, position):
            return f"'{typed}' is not part of the condition language: write '{meant}'"
    char = text[position]
    if char == "_":
        return "names cannot start with '_': percept names look like user.distance"
    return (f"unexpected character {char!r}: conditions are made of percept names, numbers with "
            "units, strings, comparisons, and/or/not and parentheses")
