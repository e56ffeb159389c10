"""Every YAML document armtool reads goes through here: PyYAML's safe loader, with a guard
against documents that aliases blow up ("billion laughs").

Ten lines of `&a [*b, *b, ...]` make a document of a billion values. PyYAML builds each anchored
node once and shares it, so loading is cheap; what follows is not: walking, serializing or
checking the values visits every copy, and a document that refers to itself never ends. So the
composed node graph is measured before anything is built from it: its size with every alias
expanded, against the nodes actually written. A document whose aliases add more than
MAX_ALIAS_NODES nodes, or that contains itself, is refused with a MarkedYAMLError at the anchor
that does it (so every caller's "invalid YAML at file:line" handling reports it). Real files use
anchors for a few shared defaults (`<<: *defaults`): a few hundred nodes at most.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import yaml

MAX_ALIAS_NODES = 100_000  # nodes that aliases may add to a document


class AliasBomb(yaml.MarkedYAMLError):
    """A document whose aliases expand it far beyond what was written, or that contains itself."""


def _children(node: yaml.Node) -> list[yaml.Node]:
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    if isinstance(node, yaml.MappingNode):
        return [part for pair in node.value for part in pair]
    return []


def check_aliases(node: yaml.Node, text: str) -> None:
    """Raise AliasBomb when `node`, with its aliases expanded, is more than MAX_ALIAS_NODES nodes
    larger than as written, or contains itself. Linear in the nodes written (sizes are shared)."""
    if "&" not in text:
        return  # no anchor, so no alias: every node is written once
    size: dict[int, int] = {}
    referenced: dict[int, int] = {}
    open_: set[int] = set()
    stack: list[tuple[yaml.Node, bool]] = [(node, False)]
    by_id: dict[int, yaml.Node] = {}
    while stack:
        current, children_done = stack.pop()
        key = id(current)
        if children_done:
            open_.discard(key)
            size[key] = 1 + sum(size[id(child)] for child in _children(current))
            continue
        referenced[key] = referenced.get(key, 0) + 1
        if key in size:
            continue
        if key in open_:
            raise AliasBomb(
                None, None, "the document contains itself through an alias (an endless document)", current.start_mark
            )
        open_.add(key)
        by_id[key] = current
        stack.append((current, True))
        stack.extend((child, False) for child in reversed(_children(current)))
    written = len(size)
    expanded = size[id(node)]
    if expanded - written > MAX_ALIAS_NODES:
        shared = [k for k, n in referenced.items() if n > 1]
        worst = max(shared, key=lambda k: size[k] * referenced[k]) if shared else id(node)
        raise AliasBomb(
            None,
            None,
            f"aliases expand the document to {expanded:.3g} nodes from {written} written (armtool allows "
            f"{MAX_ALIAS_NODES} more than written; a 'billion laughs' document?)",
            by_id[worst].start_mark,
        )


def _checked_documents(loader: yaml.SafeLoader, text: str) -> Iterator[yaml.Node]:
    """The node graph of each non-empty document of the stream, checked before it is returned."""
    while loader.check_node():
        node = loader.get_node()
        if node is not None:
            check_aliases(node, text)
            yield node


def compose_all(text: str) -> list[yaml.Node]:
    """The node graph of every document (None documents dropped), each checked."""
    loader = yaml.SafeLoader(text)
    try:
        return list(_checked_documents(loader, text))
    finally:
        loader.dispose()


def compose(text: str) -> yaml.Node | None:
    """The node graph of a single-document stream, checked (None when it is empty)."""
    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
        if node is not None:
            check_aliases(node, text)
        return node
    finally:
        loader.dispose()


def safe_load_all(text: str) -> list[Any]:
    """yaml.safe_load_all, checked: the Python value of every document (empty ones dropped)."""
    loader = yaml.SafeLoader(text)
    try:
        docs = [loader.construct_document(node) for node in _checked_documents(loader, text)]
        return [d for d in docs if d is not None]
    finally:
        loader.dispose()


def safe_load(text: str) -> Any:
    """yaml.safe_load, checked."""
    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        check_aliases(node, text)
        return loader.construct_document(node)
    finally:
        loader.dispose()
