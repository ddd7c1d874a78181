"""Python values as TOML: the values of Scene.set and the documents of Scene.from_dict."""

import json
import math
import numbers
import os
import re

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


class TomlValueError(ValueError):
    """A value that has no TOML form; `where` is the key it was given for."""

    def __init__(self, message, where):
        super().__init__(message)
        self.where = where


def _key(k, where):
    if not isinstance(k, str):
        raise TomlValueError(f"keys must be strings, got {type(k).__name__} {k!r}", where)
    return k if _BARE_KEY.match(k) else json.dumps(k, ensure_ascii=False)


def toml_value(v, where="value"):
    """The TOML literal of a Python value: bool, int, float (nan, inf), str, os.PathLike,
    list, tuple or 1-D/2-D NumPy array (arrays), dict (inline table)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        f = float(v)
        if math.isnan(f):
            return "nan"
        if math.isinf(f):
            return "inf" if f > 0 else "-inf"
        return repr(f)
    if isinstance(v, os.PathLike):
        v = os.fspath(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if hasattr(v, "tolist") and not isinstance(v, (list, tuple, dict)):
        v = v.tolist()  # NumPy arrays and scalars
        if not isinstance(v, list):
            return toml_value(v, where)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x, f"{where}[{i}]") for i, x in enumerate(v)) + "]"
    if isinstance(v, dict):
        items = (f"{_key(k, where)} = {toml_value(x, f'{where}.{k}')}" for k, x in v.items())
        return "{ " + ", ".join(items) + " }"
    raise TomlValueError(f"a value of type {type(v).__name__} has no TOML form: {v!r}", where)


def _is_table_array(v):
    return isinstance(v, (list, tuple)) and len(v) > 0 and all(isinstance(x, dict) for x in v)


def to_toml(document):
    """A nested dict as a TOML document: dicts become [tables], lists of dicts [[arrays of
    tables]], everything else `key = value`."""
    if not isinstance(document, dict):
        raise TomlValueError(f"a scene is a dict of keys, got {type(document).__name__}", "<dict>")
    lines = []

    def emit(table, path):
        header = ".".join(_key(k, ".".join(path)) for k in path)
        for k, v in table.items():
            if not isinstance(v, dict) and not _is_table_array(v):
                where = ".".join(path + [str(k)])
                lines.append(f"{_key(k, where)} = {toml_value(v, where)}")
        for k, v in table.items():
            if isinstance(v, dict):
                lines.append("")
                lines.append(f"[{header + '.' if header else ''}{_key(k, header)}]")
                emit(v, path + [k])
        for k, v in table.items():
            if _is_table_array(v):
                for item in v:
                    lines.append("")
                    lines.append(f"[[{header + '.' if header else ''}{_key(k, header)}]]")
                    emit(item, path + [k])

    emit(document, [])
    return "\n".join(lines) + "\n"
