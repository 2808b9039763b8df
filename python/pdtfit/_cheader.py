"""Enum constants read from pdtfit's C headers, so that no status code,
cost kind or rule number is typed a second time in Python.

Dependency-free: the tools' test support (tools/pdtsupport) reads the
repository's headers with it too.
"""
import pathlib
import re

_MEMBER = re.compile(r"(?:^|[{,])\s*(PDT_[A-Z0-9_]+)\s*=\s*(-?\d+)\s*(?=,|$)", re.M)
_ENUM = re.compile(r"typedef\s+enum\s+(\w+)\s*\{(.*?)\}\s*(\w+)\s*;", re.S)


def enums(path):
    """{typedef name: {member: value}} of every `typedef enum` in the header."""
    text = pathlib.Path(path).read_text(encoding="utf-8")
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return {typedef: {m: int(v) for m, v in _MEMBER.findall(body)}
            for _, body, typedef in _ENUM.findall(text)}


def defines(path):
    """{name: value} of every `#define PDT_NAME <integer>` in the header;
    of a name defined in several branches, the first (pdt_config.h's
    defaults that follow SIZE_MAX give a host's size_t first)."""
    text = pathlib.Path(path).read_text(encoding="utf-8")
    out = {}
    for m, v in re.findall(r"^#define\s+(PDT_\w+)\s+(\d+)u?\s", text, re.M):
        out.setdefault(m, int(v))
    return out


def status_names(path):
    """{value: name} of pdt_status_t, the name without PDT_ / PDT_ERR_
    ("NO_EXCITATION", "OK", "RUNNING")."""
    members = enums(path)["pdt_status_t"]
    return {v: re.sub(r"^PDT_(ERR_)?", "", m) for m, v in members.items()}
