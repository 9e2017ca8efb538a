"""Languages of an application: which tags are languages, and what a language is called.

An application declares the languages its texts are written in (`<dialog language="en"
languages="en de">`); each text without `xml:lang` is in the default `language`, each other
language's text carries `xml:lang`. A language is an ISO 639-1 code, optionally with a region
(`en`, `de`, `en-us`, `de-AT`), the way espeak-ng names its voices too; anything else
(`klingon`, `english`) is refused by the checker. Pure: no file, no process.
"""
from __future__ import annotations

import re

XML_LANG = "{http://www.w3.org/XML/1998/namespace}lang"
DEFAULT_LANGUAGE = "en"
ISO_639_1 = frozenset("""
aa ab ae af ak am an ar as av ay az ba be bg bh bi bm bn bo br bs ca ce ch co cr cs cu cv cy
da de dv dz ee el en eo es et eu fa ff fi fj fo fr fy ga gd gl gn gu gv ha he hi ho hr ht hu
hy hz ia id ie ig ii ik io is it iu ja jv ka kg ki kj kk kl km kn ko kr ks ku kv kw ky la lb
lg li ln lo lt lu lv mg mh mi mk ml mn mr ms mt my na nb nd ne ng nl nn no nr nv ny oc oj om
or os pa pi pl ps pt qu rm rn ro ru rw sa sc sd se sg si sk sl sm sn so sq sr ss st su sv sw
ta te tg th ti tk tl tn to tr ts tt tw ty ug uk ur uz ve vi vo wa wo xh yi yo za zh zu
""".split())
NAMES = {"en": "English", "de": "German", "fr": "French", "es": "Spanish", "it": "Italian",
         "nl": "Dutch", "pt": "Portuguese", "pl": "Polish", "sv": "Swedish", "da": "Danish"}
_TAG = re.compile(r"([A-Za-z]{2})(?:[-_]([A-Za-z]{2}|[0-9]{3}))?")


def is_language(tag: str) -> bool:
    """True for an ISO 639-1 code with an optional region: en, de, en-us, de-AT, pt_BR."""
    match = _TAG.fullmatch(tag.strip())
    return bool(match) and match.group(1).lower() in ISO_639_1


def base_language(tag: str) -> str:
    """The language without its region: 'en-us' -> 'en', 'de-AT' -> 'de'."""
    return tag.strip().lower().replace("_", "-").split("-")[0]


def language_name(tag: str) -> str:
    """'German (de)' for messages; the bare tag for a language without a name here."""
    base = base_language(tag)
    return f"{NAMES[base]} ({tag})" if base in NAMES else tag


def not_a_language(tag: str) -> str:
    """The message for a tag that is not a language."""
    return (f"'{tag}' is not a language: write an ISO 639-1 code, optionally with a region "
            f"(en, de, fr, en-us, de-at)")


def declared_languages(language: str | None, languages: str | None) -> tuple[str, ...]:
    """The application's languages, the default first, each once (as their base codes)."""
    found = [base_language(t) for t in (languages or "").replace(",", " ").split()]
    default = base_language(language) if language else (found[0] if found else DEFAULT_LANGUAGE)
    return tuple(dict.fromkeys([default, *found]))
