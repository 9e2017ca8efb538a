"""Tokens of the condition language: the first gate of the closed grammar.

Only what the grammar needs is a token; anything else (`.` after a string, `[`, `:`, `_` names,
`{`, backslashes, lambdas' colons…) stops here with the column, so no user text ever reaches Python.
Where the stray text is a known slip (`&&`, `≤`, `0,75m`, “yes”, `AND`) the message says what to
write instead (the tables are in hints.py).
"""
from __future__ import annotations

import re
from typing import NamedTuple

from ..exceptions import ConditionError
from .hints import (ARITHMETIC, KEYWORDS, OPERATORS, STRAY, SYMBOLS, TYPOGRAPHIC_QUOTES, ascii_equivalent,
                    keyword_case, symbol_at, unit_alias, unit_on_name, unit_suggestion)
from .units import UNITS

__all__ = ["KEYWORDS", "Token", "tokenize"]


class Token(NamedTuple):
    kind: str      # NUMBER, STRING, NAME, KEYWORD, OP, LPAREN, RPAREN, END
    text: str      # the source text of the token (the decoded value for STRING)
    offset: int    # 0-based index into the condition text
    end: int       # index just past the token


_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*(?:\.[A-Za-z][A-Za-z0-9_]*)*")
_NUMBER_TEXT = r"-?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
_MASTER = re.compile(rf"""
    (?P<space>\s+)
  | (?P<number>{_NUMBER_TEXT})
  | (?P<name>[A-Za-z][A-Za-z0-9_]*(?:\.[A-Za-z][A-Za-z0-9_]*)*)
  | (?P<op>[<>=!]+)
  | (?P<lparen>\()
  | (?P<rparen>\))
""", re.VERBOSE)
_KINDS = {"number": "NUMBER", "lparen": "LPAREN", "rparen": "RPAREN"}
_WORD = re.compile(r"[^\W\d_]+")


def tokenize(text: str) -> list[Token]:
    """The tokens of `text`, ending with an END token; ConditionError on the first stray character."""
    tokens = scan(text)
    if len(tokens) > 1 and tokens[-2].kind == "ERROR":
        raise ConditionError(tokens[-2].text, tokens[-2].offset, text)
    return tokens


def scan(text: str) -> list[Token]:
    """As `tokenize`, but the first stray character becomes an ERROR token (its text the
    message) followed by END, so the parser can report an earlier slip first."""
    tokens: list[Token] = []
    try:
        _scan(text, tokens)
    except ConditionError as problem:
        tokens.append(Token("ERROR", problem.reason, problem.offset, problem.offset))
    tokens.append(Token("END", "", len(text), len(text)))
    return tokens


def _scan(text: str, tokens: list[Token]) -> None:
    position, length = 0, len(text)
    match_at = _MASTER.match
    while position < length:
        match = match_at(text, position)
        if match is None:
            if text[position] in "\"'":
                _refuse_quote_in_number(text, position, tokens)
                token = _string_token(text, position)
                tokens.append(token)
                position = token.end
                continue
            raise ConditionError(_stray_message(text, position, tokens), position, text)
        kind, end = match.lastgroup, match.end()
        if kind == "name":
            tokens.append(_word_token(text, match))
        elif kind == "op":
            tokens.append(_operator_token(text, match, tokens))
        elif kind != "space":
            tokens.append(Token(_KINDS[kind], match.group(), position, end))
        position = end


def _word_token(text: str, match: re.Match) -> Token:
    word, position, end = match.group(), match.start(), match.end()
    if end < len(text) and text[end] in "_.":
        _refuse_name_continuation(text, match)
    meant = keyword_case(word)
    if meant is not None:
        raise ConditionError(f"'{word}' is written in lower case: write '{meant}'", position, text)
    return Token("KEYWORD" if word in KEYWORDS else "NAME", word, position, end)


def _refuse_name_continuation(text: str, match: re.Match) -> None:
    end, word = match.end(), match.group()
    rest = text[end + 1:]
    if text[end] == "." and rest.strip() == "":
        raise ConditionError("a condition does not end with '.': delete it", end, text)
    following = _NAME.match(rest.lstrip()) if text[end] == "." and rest[:1].isspace() else None
    if following is not None:        # (a letter outside A-Z, as 'é', starts no name: below)
        raise ConditionError(f"no spaces inside a name: write {word}.{following.group()}",
                             end, text)
    raise ConditionError(
        f"'{text[end]}' cannot follow '{word}' here: names are letters, digits and "
        "underscores, parts joined by single dots, e.g. user.distance", end, text)


def _operator_token(text: str, match: re.Match, tokens: list[Token]) -> Token:
    written, position = match.group(), match.start()
    previous = tokens[-1] if tokens else None
    if previous is not None and previous.kind == "OP":
        _refuse_split_operator(text, previous.text, written, previous.offset, position)
    if written not in OPERATORS:
        following = re.match(r"\s+([<>=!]+)", text[match.end():])
        if following:
            _refuse_split_operator(text, written, following.group(1), position, position)
        meant = SYMBOLS.get(written)
        if meant is not None:
            raise ConditionError(_symbol_message(written, meant), position, text)
        raise ConditionError(f"'{written}' is not an operator: compare with one of "
                             f"{' '.join(OPERATORS)}", position, text)
    return Token("OP", written, position, match.end())


def _refuse_split_operator(text: str, first: str, second: str, start: int,
                           position: int) -> None:
    """`< =`, `! =`: an operator split by a space; other pairs are two operators in a row."""
    joined = first + second
    meant = joined if joined in OPERATORS else SYMBOLS.get(joined)
    if meant is not None and meant in OPERATORS:
        raise ConditionError(f"no space inside an operator: write '{meant}'", start, text)
    raise ConditionError(f"two operators in a row ('{first}' then '{second}'): write one of "
                         f"{' '.join(OPERATORS)}", position, text)


def _symbol_message(written: str, meant: str) -> str:
    return f"'{written}' is not part of the condition language: write '{meant}'"


def _refuse_quote_in_number(text: str, position: int, tokens: list[Token]) -> None:
    """1'000 (Swiss thousands) is a number with a separator, not the start of a string."""
    previous = tokens[-1] if tokens else None
    if (previous is not None and previous.kind == "NUMBER" and previous.end == position
            and text[position + 1:position + 2].isdigit()):
        raise ConditionError(_separator_message(text, previous.offset, position), position, text)


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


# ---------------------------------------------------------------- stray characters

def _stray_message(text: str, position: int, tokens: list[Token]) -> str:
    """What the character at `position` probably was meant to be, and what to write."""
    char = text[position]
    previous = tokens[-1] if tokens else None
    glued_number = previous is not None and previous.kind == "NUMBER" and previous.end == position
    if glued_number and char in ",_" and text[position + 1:position + 2].isdigit():
        return _separator_message(text, previous.offset, position)
    if previous is not None and previous.kind == "NUMBER":
        word = _WORD.match(text, position)
        spelled = word.group() if word else char
        suggestion = unit_suggestion(previous.text, spelled)
        if suggestion:
            joint = (": write " if glued_number else
                     ", and a unit goes right after the number: write ")
            return f"unknown unit '{spelled}'{joint}{suggestion}"
    if char in TYPOGRAPHIC_QUOTES:
        return _quote_message(text, position)
    symbol = symbol_at(text, position)
    if symbol is not None:
        return _symbol_message(symbol, SYMBOLS[symbol])
    run = _foreign_run(text, position)
    if run:
        return (f"{run!r} is not plain ASCII: write {ascii_equivalent(run)} "
                "(digits 0-9, letters a-z, operators < > = !)")
    if char == "_":
        return "names cannot start with '_': percept names look like user.distance"
    if char == "." and previous is not None and previous.kind == "NAME":
        following = _NAME.match(text[position + 1:].lstrip())
        if following:
            return f"no spaces inside a name: write {previous.text}.{following.group()}"
    if char == "-":
        return ("'-' is only a sign, right before a number (-1): conditions do no arithmetic"
                if text[position + 1:position + 2].isspace() or position + 1 == len(text) else
                "conditions do no arithmetic: compare a percept with a number, e.g. "
                "user.distance < 0.75m")
    if char in "[" and previous is not None and previous.kind == "NAME":
        inside = re.match(r"\[\s*([^\]\s]*)\s*\]", text[position:])
        if inside and (inside.group(1) in UNITS or unit_alias(inside.group(1))):
            return unit_on_name(previous.text, inside.group(1))
    if glued_number and char == ":" and re.fullmatch(r"[0-9]+", previous.text) and \
            re.match(r":[0-9]{2}(?![0-9])", text[position:]):
        minutes, seconds = int(previous.text), int(text[position + 1:position + 3])
        return (f"'{previous.text}:{text[position + 1:position + 3]}' is not a number: write "
                f"{minutes * 60 + seconds}s")
    if char in ARITHMETIC:
        return ("conditions do no arithmetic: write the result as one number with its unit, "
                "e.g. 0.5 or 90s")
    if char in STRAY:
        return STRAY[char]
    return (f"unexpected character {char!r}: conditions are made of percept names, numbers with "
            "units, strings, comparisons, and/or/not and parentheses")


def _foreign_run(text: str, position: int) -> str:
    """The non-ASCII characters from `position` on that have ASCII twins (١٢, １２, ＜), or ''."""
    end = position
    while end < len(text) and not text[end].isascii() and ascii_equivalent(text[end]):
        end += 1
    return text[position:end]


def _separator_message(text: str, start: int, position: int) -> str:
    """A decimal comma (0,75m) or a thousands separator (1,000 1_000 1'000 1.000,5) in a number."""
    number = re.match(r"-?\.?[0-9]+(?:[,_'.][0-9]+)*", text[start:]).group()
    unit = _NAME.match(text, start + len(number))
    unit_text = unit.group() if unit else ""
    separators = re.findall(r"[,_'.]", number)
    groups = re.split(r"[,_'.]", number.lstrip("-"))
    if "," in separators and (separators[-1] == "," and (len(separators) > 1 or
                                                         len(groups[-1]) != 3 or groups[0] == "0")):
        meant = "".join(re.split(r"[_'.]", number.replace(",", ".")[:number.rfind(",")])) + \
            "." + groups[-1]
        return (f"decimal comma in {number}{unit_text}: write {meant}{unit_text} (decimals are "
                f"written with a point; numbers have no thousands separators)")
    separator = text[position]
    plain = number.replace(separator, "")
    hint = (f"; for a decimal write {number.replace(',', '.', 1)}{unit_text}"
            if separators == [","] else "")
    return (f"'{separator}' inside the number {number}: write {plain}{unit_text} (numbers have "
            f"no thousands separators){hint}")


def _quote_message(text: str, position: int) -> str:
    closing = next((i for i in range(position + 1, len(text))
                    if text[i] in TYPOGRAPHIC_QUOTES or text[i] in "\"'"), None)
    inner = text[position + 1:closing] if closing is not None else text[position + 1:]
    return (f"typographic quote {text[position]!r}: write straight quotes, e.g. "
            f"\"{inner.strip() or 'yes'}\" (an editor may have replaced them)")
