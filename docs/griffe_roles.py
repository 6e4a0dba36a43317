"""A griffe extension for the API reference: the Sphinx roles in the docstrings made Markdown.

The docstrings cross-reference with reStructuredText roles (``:mod:`~transplanter.geometry.teeth```,
``:class:`Study```, ``:func:`gear_pair```), which mkdocstrings would print as they are. Each role
becomes a link to the object's place in the API reference when the object has one there (a public
module, or a documented public class, function, method or attribute in one), resolved like Sphinx
resolves it — the full path, or a name relative to the object's module or class; otherwise it
becomes plain code. ``~`` shows the last part of the path only. Loaded by ``mkdocs.yml``
(``extensions`` of the python handler); it changes nothing in the package.

The package documents its constants and fields with ``#:`` comments above them (as Sphinx's
autodoc reads them; ``core.tolerances`` is all such constants): griffe reads only a string after an
assignment, so those comments become the attribute's docstring first, and the constants appear in
the reference with their reasons.
"""

from __future__ import annotations

import re

import griffe

ROLE = re.compile(r":(?:mod|class|func|meth|attr|data|exc|obj):`(~?)([^`<>]+?)`")
#: a documentation comment line, as autodoc reads them: ``#: text`` on the lines above an assignment
COMMENT = re.compile(r"^\s*#:\s?(.*)$")


def _comment_docstrings(obj) -> None:
    """Every attribute under ``obj`` without a docstring gets the ``#:`` lines right above it."""
    for member in list(obj.members.values()):
        if member.is_alias:
            continue
        if member.is_attribute and member.docstring is None and member.lineno:
            source = member.module.lines
            found, k = [], member.lineno - 2
            while k >= 0 and (m := COMMENT.match(source[k])):
                found.insert(0, m.group(1))
                k -= 1
            if found:
                member.docstring = griffe.Docstring("\n".join(found), lineno=k + 2, parent=member)
        elif member.is_module or member.is_class:
            _comment_docstrings(member)


def _rendered(obj) -> bool:
    """Whether mkdocstrings gives ``obj`` an anchor: public all the way up, documented if not a module."""
    try:
        while obj.is_alias:
            obj = obj.final_target
    except (griffe.AliasResolutionError, griffe.CyclicAliasError):
        return False
    node = obj
    while node is not None:
        if node.name.startswith("_") and node.name != "__init__":
            return False
        if not node.is_module and not node.docstring:
            return False
        node = node.parent
    return True


def _find(root, path: str):
    try:
        obj = root.modules_collection[path] if hasattr(root, "modules_collection") else None
    except KeyError:
        obj = None
    return obj


class SphinxRoles(griffe.Extension):
    """Rewrites every docstring of the package once it is loaded."""

    def on_package(self, *, pkg, **kwargs) -> None:  # griffe >= 1.0
        _comment_docstrings(pkg)
        self._walk(pkg, pkg)

    def _walk(self, obj, pkg) -> None:
        if obj.is_alias:
            return
        if obj.docstring:
            obj.docstring.value = ROLE.sub(lambda m: self._replace(m, obj, pkg), obj.docstring.value)
        for member in list(obj.members.values()):
            if not member.is_alias:
                self._walk(member, pkg)

    def _resolve(self, name: str, where, pkg):
        name = name.strip().removesuffix("()")
        candidates = [name]
        scope = where
        while scope is not None:  # relative to the object, its class, its module, its packages
            candidates.append(f"{scope.path}.{name.lstrip('.')}")
            scope = scope.parent
        for path in candidates:
            if not path.startswith(pkg.name + ".") and path != pkg.name:
                continue
            try:
                obj = pkg.modules_collection[path]
            except KeyError:
                continue
            return obj
        return None

    def _replace(self, match: re.Match, where, pkg) -> str:
        tilde, name = match.groups()
        shown = name.strip().split(".")[-1] if tilde else name.strip().lstrip(".")
        obj = self._resolve(name, where, pkg)
        if obj is None or not _rendered(obj):
            return f"`{shown}`"
        target = obj.final_target.path if obj.is_alias else obj.path
        return f"[`{shown}`][{target}]"
