"""YAML for scenarios, bounded: a scenario is data, and data has a size.

PyYAML's SafeLoader runs no code, but a few hundred bytes of nested aliases (`&a [*a, *a, ...]`,
"billion laughs") stand for billions of values: anything that walks them (a message's repr, a
check) then runs for minutes and gigabytes. And the composer recurses per nesting level, so
`[[[[...` 1,000 deep is a RecursionError. `load` refuses, while composing and so before any
value is built, a document past these limits (docs/limits.md), with a YAMLError at the place:

- MAX_BYTES: the text of a file or a --set value;
- MAX_DEPTH: nested sequences and mappings;
- MAX_NODES: values counted as if every alias were written out (an alias of a list of
  1,000 numbers counts 1,001), so the data that any code walks is that small;
- an alias inside its own anchor (`&a [*a]`, a list that holds itself) is refused: nothing
  that walks the data should have to expect a cycle.

An integer written with more than MAX_INT_CHARS characters is refused at the number too
(Python will not read one of over 4,300 digits: a ValueError deep in PyYAML).
"""
from __future__ import annotations

import yaml
from yaml.composer import ComposerError
from yaml.constructor import ConstructorError

MAX_BYTES = 1_000_000
MAX_DEPTH = 32
MAX_NODES = 200_000
MAX_INT_CHARS = 1_000


class BoundedLoader(yaml.SafeLoader):
    """SafeLoader that counts the nodes a document expands to and how deep it nests."""

    def __init__(self, stream):
        super().__init__(stream)
        self._depth = 0
        self._nodes = 0
        self._sizes: dict[str, int] = {}     # anchor -> the nodes its value expands to
        self._open: set[str] = set()         # anchors whose value is being composed

    def compose_node(self, parent, index):
        event = self.peek_event()
        if isinstance(event, yaml.AliasEvent):
            if event.anchor in self._open:
                raise ComposerError(None, None, f"the alias *{event.anchor} is inside its own "
                                    "anchor (a value that holds itself)", event.start_mark)
            self._count(self._sizes.get(event.anchor, 1), event)
            return super().compose_node(parent, index)
        self._depth += 1
        if self._depth > MAX_DEPTH:
            raise ComposerError(None, None, f"nested deeper than {MAX_DEPTH} levels",
                                event.start_mark)
        anchor = getattr(event, "anchor", None)
        if anchor is not None:
            self._open.add(anchor)
        before = self._nodes
        self._count(1, event)
        node = super().compose_node(parent, index)
        if anchor is not None:
            self._open.discard(anchor)
            self._sizes[anchor] = self._nodes - before
        self._depth -= 1
        return node

    def _count(self, nodes: int, event) -> None:
        self._nodes += nodes
        if self._nodes > MAX_NODES:
            raise ComposerError(None, None, f"more than {MAX_NODES:,} values (counting each "
                                "alias as the values it repeats)", event.start_mark)

    def construct_yaml_int(self, node):
        # Python refuses to read an int of over 4,300 digits (a ValueError), and YAML 1.1's
        # base-60 ints (1:30:00) are summed digit group by digit group: both stop here
        if len(str(node.value)) > MAX_INT_CHARS:
            raise ConstructorError(None, None, f"an integer of more than {MAX_INT_CHARS} "
                                   "characters", node.start_mark)
        return super().construct_yaml_int(node)


BoundedLoader.add_constructor("tag:yaml.org,2002:int", BoundedLoader.construct_yaml_int)


def _construct_object(self, node, deep=False):
    """A value its explicit tag cannot read (`!!bool maybe`, `!!int 1.5`, `!!timestamp 2001`)
    is a YAMLError at the value: PyYAML's constructors raise KeyError, ValueError or
    AttributeError for them."""
    try:
        return yaml.SafeLoader.construct_object(self, node, deep)
    except (KeyError, ValueError, AttributeError, TypeError) as exc:
        raise ConstructorError(None, None, f"cannot read {node.value!r:.80} as {node.tag} "
                               f"({type(exc).__name__})", node.start_mark) from None


BoundedLoader.construct_object = _construct_object


def too_long(text: str) -> str | None:
    """The complaint about a text over MAX_BYTES, else None."""
    size = len(text.encode("utf-8", "surrogatepass"))
    if size > MAX_BYTES:
        return f"{size:,} bytes is more than a scenario may hold ({MAX_BYTES:,} bytes)"
    return None


def load(text: str):
    """The data of one YAML document, within the limits (else a YAMLError at the place)."""
    loader = BoundedLoader(text)
    try:
        return loader.get_single_data()
    finally:
        loader.dispose()


def compose(text: str):
    """The node tree of one YAML document, within the same limits."""
    loader = BoundedLoader(text)
    try:
        return loader.get_single_node()
    finally:
        loader.dispose()
