"""Checks shared by everything that reads a file a stranger wrote (scene files, their dict form, map
YAML, model archives): a ``ValueError`` naming the file and the field, raised before any state
changes, in bounded time and memory.

- :func:`read_text`: a regular file of at most ``max_bytes``, read as UTF-8 (never the locale's
  encoding), refused naming the file otherwise;
- :func:`load_yaml`: ``yaml.SafeLoader`` (no Python object is ever built) that refuses duplicate keys
  and a document whose aliases expand past :data:`MAX_YAML_NODES` nodes (a "billion laughs" file of
  a few hundred bytes); :func:`load_json` refuses duplicate keys too;
- :func:`number`, :func:`point`, :func:`name`: a field's type, strictly: a number is an ``int`` or a
  ``float`` (numpy's too), never a ``bool`` or a ``str``;
- :func:`short`: a value's ``repr`` of bounded length, for error messages.
"""

from __future__ import annotations

import json
import math
import reprlib
from pathlib import Path

import numpy as np

#: Largest coordinate magnitude (m): observations are float32, which keeps ~6 cm resolution here.
MAX_COORDINATE = 1e6
#: Nodes a YAML document may expand to, aliases expanded (a scene of 5,000 obstacles has ~60,000).
MAX_YAML_NODES = 1_000_000
#: Longest ``name`` (characters): a label for logs and results.
MAX_NAME_LENGTH = 200
#: Longest ``repr`` in an error message (characters).
MAX_REPR = 120

_repr = reprlib.Repr()
_repr.maxlevel, _repr.maxlist, _repr.maxtuple, _repr.maxdict, _repr.maxstring, _repr.maxother = 3, 6, 6, 6, 60, 60


def short(value) -> str:
    """``repr(value)`` cut to at most :data:`MAX_REPR` characters, in time bounded whatever ``value`` holds."""
    text = _repr.repr(value)
    return text if len(text) <= MAX_REPR else text[: MAX_REPR - 3] + "..."


def is_number(value) -> bool:
    """An ``int`` or ``float`` (numpy's too); not a ``bool``, a ``str`` or anything else ``float()`` takes."""
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def number(value, field: str) -> float:
    """``value`` as a finite float, or a ``ValueError`` naming ``field``."""
    if not is_number(value):
        raise ValueError(f"{field} must be a number, got {short(value)}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{field} must be finite, got {value!r}")
    return value


def point(value, field: str) -> tuple[float, float]:
    """``value`` as a finite ``(x, y)`` of floats: a sequence (not a string or a mapping) of two numbers."""
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__") or not hasattr(value, "__iter__") or len(value) != 2:
        raise ValueError(f"{field} must be a pair of numbers (x, y), got {short(value)}")
    x, y = value
    if not (is_number(x) and is_number(y)):
        raise ValueError(f"{field} must be a pair of numbers (x, y), got {short(value)}")
    x, y = float(x), float(y)
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"{field} must be finite, got {short(value)}")
    return (x, y)


def name(value, field: str) -> str:
    """A non-empty ``str`` of at most :data:`MAX_NAME_LENGTH` characters."""
    if not isinstance(value, str) or not value.strip() or len(value) > MAX_NAME_LENGTH:
        raise ValueError(f"{field} must be a non-empty string of at most {MAX_NAME_LENGTH} characters, got {short(value)}")
    return value


# --- reading files ------------------------------------------------------------------------------


def read_text(path: Path, max_bytes: int, what: str) -> str:
    """The text of the regular file ``path`` (UTF-8, an initial BOM dropped), at most ``max_bytes`` long.

    :param what: how errors name the file (``"scenario file"``, ``"ROS map"``).
    :raises ValueError: naming the file if it does not exist, is not a regular file (a FIFO or a
        device would block or never end), is larger than ``max_bytes`` or is not UTF-8.
    """
    try:
        if not path.exists():
            raise ValueError(f"{what} {path}: does not exist")
        if not path.is_file():
            raise ValueError(f"{what} {path}: not a regular file")
        if path.stat().st_size > max_bytes:
            raise ValueError(f"{what} {path}: larger than {max_bytes} bytes")
        with open(path, "rb") as f:
            data = f.read(max_bytes + 1)  # (the file may have grown since stat)
    except OSError as error:
        raise ValueError(f"{what} {path}: cannot be read ({error.strerror or error})") from None
    if len(data) > max_bytes:
        raise ValueError(f"{what} {path}: larger than {max_bytes} bytes")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise ValueError(f"{what} {path}: not UTF-8 text (byte {error.start}: {error.reason})") from None


def _no_duplicates(pairs):
    out = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"duplicate key {short(key)}")
        out[key] = value
    return out


def load_json(text: str):
    """``json.loads`` refusing duplicate keys (a ``ValueError`` naming the key)."""
    return json.loads(text, object_pairs_hook=_no_duplicates)


def _loader_class():
    import yaml

    class Loader(yaml.SafeLoader):
        """SafeLoader that refuses duplicate keys (PyYAML keeps the last one silently)."""

        def construct_mapping(self, node, deep=False):
            if isinstance(node, yaml.MappingNode):
                seen = set()
                for key_node, _ in node.value:
                    if isinstance(key_node, yaml.ScalarNode) and key_node.tag != "tag:yaml.org,2002:merge":
                        key = (key_node.tag, key_node.value)
                        if key in seen:
                            raise yaml.constructor.ConstructorError(None, None, f"duplicate key {short(key_node.value)}", key_node.start_mark)
                        seen.add(key)
            return super().construct_mapping(node, deep=deep)

    return Loader


def _expanded_size(root, limit: int) -> int:
    """How many nodes the document holds with every alias expanded (each distinct node counted once per
    reference, memoised: linear in the distinct nodes), stopping past ``limit``; a recursive alias is a
    ``ValueError``."""
    import yaml

    sizes: dict[int, int] = {}
    stack = [(root, False)]
    open_nodes: set[int] = set()
    while stack:
        node, done = stack.pop()
        key = id(node)
        if key in sizes and not done:
            continue
        if isinstance(node, yaml.ScalarNode):
            sizes[key] = 1
            continue
        children = [n for pair in node.value for n in pair] if isinstance(node, yaml.MappingNode) else list(node.value)
        if done:
            open_nodes.discard(key)
            sizes[key] = min(1 + sum(sizes[id(c)] for c in children), limit + 1)
            continue
        if key in open_nodes:
            raise ValueError("a recursive alias (a node that contains itself)")
        open_nodes.add(key)
        stack.append((node, True))
        for child in children:
            if id(child) in open_nodes:
                raise ValueError("a recursive alias (a node that contains itself)")
            if id(child) not in sizes:
                stack.append((child, False))
    return sizes[id(root)]


def load_yaml(text: str):
    """A YAML document read with a ``SafeLoader`` that refuses duplicate keys and aliases expanding the
    document past :data:`MAX_YAML_NODES` nodes.

    :raises yaml.YAMLError: on invalid YAML or a duplicate key (the parser's message says where).
    :raises ValueError: on aliases that expand too far, or refer to themselves.
    """
    loader = _loader_class()(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        size = _expanded_size(node, MAX_YAML_NODES)
        if size > MAX_YAML_NODES:
            raise ValueError(f"its aliases expand it to more than {MAX_YAML_NODES} nodes")
        return loader.construct_document(node)
    finally:
        loader.dispose()


__all__ = ["MAX_COORDINATE", "MAX_NAME_LENGTH", "MAX_YAML_NODES", "is_number", "load_json", "load_yaml", "name", "number", "point",
           "read_text", "short"]  # fmt: skip
