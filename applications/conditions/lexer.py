"""Tokens of the condition language: the first gate of the closed grammar.

Only what the grammar needs is a token; anything else (`.` after a string, `[`, `:`, `_` names,
`{`, backslashes, lambdas' colons…) stops here with the column, so no user text ever reaches Python.
"""
from __future__ import annotations

import re
from typing import NamedTuple

from ..exceptions import ConditionError

KEYWORDS = frozenset({"and", "or", "not", "true", "false"})

# What people from other languages type, and what to write instead.
_HINTS = {"&&": "and", "||": "or", "!": "not", "=": "==", "<>": "!=", "&": "and", "|": "or"}


class Token(NamedTuple):
    kind: str      # NUMBER, STRING, NAME, KEYWORD, OP, LPAREN, RPAREN, END
    text: str      # the source text of the token (the decoded value for STRING)
    offset: int    # 0-based index into the condition text
    end: int       # index just past the token


_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*(?:\.[A-Za-z][A-Za-z0-9_]*)*")


_MASTER = re.compile(r"""
    (?P<space>\s+)
  | (?P<number>(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)
  | (?P<name>[A-Za-z][A-Za-z0-9_]*(?:\.[A-Za-z][A-Za-z0-9_]*)*)
  | (?P<op><=|>=|==|!=|<(?!>)|>)
  | (?P<lparen>\()
  | (?P<rparen>\))
""", re.VERBOSE)
_KINDS = {"number": "NUMBER", "op": "OP", "lparen": "LPAREN", "rparen": "RPAREN"}


def tokenize(text: str) -> list[Token]:
    """The tokens of `text`, ending with an END token; ConditionError on the first stray character."""
    tokens: list[Token] = []
    position, length = 0, len(text)
    match_at = _MASTER.match
    while position < length:
        match = match_at(text, position)
        if match is None:
            if text[position] in "\"'":
                token = _string_token(text, position)
                tokens.append(token)
                position = token.end
                continue
            raise ConditionError(_stray_message(text, position), position, text)
        kind, end = match.lastgroup, match.end()
        if kind == "name":
            if end < length and text[end] in "_.":
                _name_token(text, position)          # raises with the explanation
            word = match.group()
            tokens.append(Token("KEYWORD" if word in KEYWORDS else "NAME", word, position, end))
        elif kind != "space":
            tokens.append(Token(_KINDS[kind], match.group(), position, end))
        position = end
    tokens.append(Token("END", "", length, length))
    return tokens


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
