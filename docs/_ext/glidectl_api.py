"""Sphinx extension: the API reference generated from ``glidectl.API_GROUPS`` at build time.

On ``builder-inited`` it writes, under ``<srcdir>/api/`` (ignored by git):

* ``index.rst``: one toctree entry per group of ``glidectl.API_GROUPS``, in the dict's order, then the modules;
* ``<group>.rst``: the group's names in autosummary tables (classes, exceptions, functions, modules, constants)
  and a hidden toctree of the object pages;
* ``generated/glidectl.<name>.rst``: one page per public name, ``autoclass`` (with ``:members:``),
  ``autoexception``, ``autofunction`` or ``automodule``, rendered by numpydoc, or ``py:data`` with the constant's
  ``#:`` comment; then the gallery scripts that use it (sphinx-gallery's ``minigallery``);
* ``modules/<module>.rst``: the glidectl modules and the non-public objects that public docstrings refer to
  (``:data:`HYDRO_SPECS```, ``:func:`glidectl.plotting.plot_locus```, ``:mod:`glidectl.uncertainty```), found by
  scanning the docstrings (and those of the objects so added, until nothing new turns up), so that every such
  reference has a target.

A file is rewritten only when its text changes (incremental builds stay incremental) and pages that are no longer
generated are deleted: the reference cannot drift from the code.

Docstrings name objects as Python does in the module that *defines* them (``:class:`Vehicle``` in
``glidectl.params``), while the pages document them under their public name (``glidectl.Vehicle``). On
``missing-reference`` the target is looked up the same way (the defining class, the defining module, then
``glidectl``) and the reference is pointed at the page that documents the object found; a dataclass field or other
attribute without an entry of its own links to its class, whose "Attributes" list describes it. A target that
names no object stays a broken reference, which ``-n`` reports.
"""

from __future__ import annotations

import importlib
import inspect
import re
import sys
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

from docutils import nodes
from sphinx.application import Sphinx
from sphinx.environment import BuildEnvironment
from sphinx.pycode import ModuleAnalyzer
from sphinx.util import logging

logger = logging.getLogger(__name__)

PACKAGE = "glidectl"
OUT_DIR = "api"  # relative to the Sphinx source directory
#: section of a group page per kind of object, in page order
SECTIONS = (("class", "Classes"), ("exception", "Exceptions"), ("function", "Functions"),
            ("module", "Modules"), ("data", "Constants"))
#: a cross-reference role in a docstring: ``:func:`name```, ``:py:class:`~name```, ``:meth:`text <name>```
ROLE = re.compile(r":(?:py:)?(?:func|meth|class|data|attr|mod|obj|exc|const):`(?:[^`<]*<)?[~.]*([\w.]+)>?`")

#: longest ``repr`` of a constant shown as its value on the page
VALUE_REPR_MAX = 100
#: docname of each public object page -> the module that defines the object it documents
PAGE_HOME: dict[str, str] = {}


@dataclass(frozen=True)
class Field:
    """A class attribute that exists only on instances (a dataclass field, an annotated attribute)."""

    owner: type
    name: str


# --- finding objects the way Python names them -------------------------------------------------------------------

def object_kind(obj: Any) -> str:
    """``"module"``, ``"exception"``, ``"class"``, ``"function"`` or ``"data"``: which autodoc directive fits."""
    if inspect.ismodule(obj):
        return "module"
    if inspect.isclass(obj):
        return "exception" if issubclass(obj, BaseException) else "class"
    return "function" if callable(obj) else "data"


def _fields(cls: type) -> set[str]:
    names: set[str] = set()
    for klass in inspect.getmro(cls):
        names |= set(getattr(klass, "__dataclass_fields__", {})) | set(vars(klass).get("__annotations__", {}))
    return names


def lookup(dotted: str) -> tuple[bool, Any]:
    """(found, object) for a dotted name: the longest importable module prefix, then attributes; an instance
    attribute of a class is found as a :class:`Field`."""
    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        except Exception:  # not a module path at all
            return False, None
        for j, attr in enumerate(parts[i:], i):
            try:
                obj = getattr(obj, attr)
            except AttributeError:
                if inspect.isclass(obj) and j == len(parts) - 1 and attr in _fields(obj):
                    return True, Field(obj, attr)
                return False, None
            except Exception:  # a descriptor that raises on the class
                return False, None
        return True, obj
    return False, None


def locate(target: str, contexts: Sequence[str]) -> tuple[str, Any] | None:
    """The first ``(dotted name, object)`` that ``target`` names, read in each context (a module or a class path)
    in turn; a target starting with the package name is absolute."""
    for ctx in contexts if not target.startswith(PACKAGE + ".") else [""]:
        dotted = f"{ctx}.{target}" if ctx else target
        found, obj = lookup(dotted)
        if found:
            return dotted, obj
    return None


def aliases() -> dict[int, str]:
    """id of every public class, function and module -> its documented name ``glidectl.<name>``."""
    pkg = importlib.import_module(PACKAGE)
    return {id(obj): f"{PACKAGE}.{n}" for n in pkg.__all__
            if inspect.isclass(obj := getattr(pkg, n)) or inspect.isroutine(obj) or inspect.ismodule(obj)}


def documented_names(dotted: str, obj: Any, alias: dict[int, str]) -> list[str]:
    """The names under which ``obj`` (found as ``dotted``) may be documented, best first."""
    if isinstance(obj, Field):
        owner = documented_names(f"{obj.owner.__module__}.{obj.owner.__qualname__}", obj.owner, alias)
        return [f"{o}.{obj.name}" for o in owner] + owner
    out = [alias[id(obj)]] if id(obj) in alias else []
    pkg = importlib.import_module(PACKAGE)
    last = dotted.rpartition(".")[2]
    if last in pkg.__all__ and getattr(pkg, last) is obj:  # a public constant, found where it is defined
        out.append(f"{PACKAGE}.{last}")
    if inspect.ismodule(obj):
        out.append(obj.__name__)
    elif inspect.isclass(obj) or inspect.isroutine(obj):
        out.append(f"{obj.__module__}.{obj.__qualname__}")
    head, _, attr = dotted.rpartition(".")
    found, parent = lookup(head) if head else (False, None)
    if found and inspect.isclass(parent):  # a member: under its class's documented names, else the class itself
        owner = documented_names(head, parent, alias)
        out += [f"{o}.{attr}" for o in owner] + owner
    out.append(dotted)
    return list(dict.fromkeys(out))


def is_public(dotted: str, obj: Any, alias: dict[int, str]) -> bool:
    """Whether ``obj`` (found as ``dotted``) has a page of its own as ``glidectl.<name>``."""
    last = dotted.rpartition(".")[2]
    pkg = importlib.import_module(PACKAGE)
    return id(obj) in alias or (last in pkg.__all__ and getattr(pkg, last) is obj)


def _class_context(cls: Any) -> str:
    return f"{cls.__module__}.{cls.__qualname__}" if inspect.isclass(cls) else ""


# --- which non-public objects need a page -----------------------------------------------------------------------

def _members(cls: type) -> Iterator[tuple[str, Any]]:
    """The members of ``cls`` that ``autoclass :members:`` documents (own, with a docstring)."""
    for name, value in vars(cls).items():
        if name.startswith("_"):
            continue
        func = value.fget if isinstance(value, property) else getattr(value, "__func__", value)
        if (inspect.isroutine(func) or isinstance(value, property)) and inspect.getdoc(func):
            yield name, func


def _see_also(doc: str) -> list[str]:
    """Names in the numpydoc "See Also" section of ``doc``."""
    if "See Also" not in doc:
        return []
    try:
        from numpydoc.docscrape import NumpyDocString

        parsed = NumpyDocString(doc)
    except Exception:  # numpydoc warns about it when the page is built
        return []
    return [name for funcs, _ in parsed["See Also"] for name, _role in funcs]


@dataclass(frozen=True)
class Constant:
    """A module-level constant: its documentation is the ``#:`` comment in ``module``, not a docstring."""

    module: str
    name: str


def references(obj: Any, module_members: bool) -> Iterator[tuple[str, list[str]]]:
    """``(target, contexts)`` of every cross-reference in the docstrings that documenting ``obj`` renders (for a
    module, with ``module_members``, its members' too)."""
    if isinstance(obj, Constant):
        value = getattr(importlib.import_module(obj.module), obj.name)
        docs = [("\n".join(data_doc(obj.name, value, [obj.module] if obj.module != PACKAGE else None)),
                 [obj.module, PACKAGE])]
        yield from ((t, ctx) for doc, ctx in docs for t in ROLE.findall(doc))
        return
    home = obj.__name__ if inspect.ismodule(obj) else getattr(obj, "__module__", None) or PACKAGE
    docs = [(inspect.getdoc(obj) or "", [home, PACKAGE])]
    if inspect.isclass(obj):
        docs += [(inspect.getdoc(m) or "", [_class_context(obj), home, PACKAGE]) for _, m in _members(obj)]
    elif inspect.ismodule(obj) and module_members:
        docs += [(inspect.getdoc(m) or "", [home, PACKAGE]) for m in _module_members(obj)]
    for doc, contexts in docs:
        for target in [*ROLE.findall(doc), *_see_also(doc)]:
            yield target, contexts


def _module_members(module: ModuleType) -> list[Any]:
    """What ``automodule :members:`` documents: ``__all__``, else the public objects the module defines."""
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n, v in vars(module).items() if not n.startswith("_")
                 and getattr(v, "__module__", None) == module.__name__]
    return [getattr(module, n) for n in names if hasattr(module, n)]


def _owner(dotted: str, obj: Any) -> tuple[str, Any]:
    """The class that documents a member or instance attribute (its outermost class), else the object itself."""
    while True:
        if isinstance(obj, Field):
            dotted, obj = dotted.rpartition(".")[0], obj.owner
            continue
        head = dotted.rpartition(".")[0]
        found, parent = lookup(head) if head else (False, None)
        if not (found and inspect.isclass(parent)):
            return dotted, obj
        dotted, obj = head, parent


def internal_objects(public: Iterable[str]) -> dict[str, dict[str, Any]]:
    """Non-public glidectl modules and objects that the docstrings of the ``public`` names refer to, and, in turn,
    those that theirs refer to: module name -> {documented name: object}."""
    alias = aliases()
    pkg = importlib.import_module(PACKAGE)
    todo = [Constant(PACKAGE, n) if object_kind(getattr(pkg, n)) == "data" else getattr(pkg, n) for n in public]
    public_ids = {id(obj) for obj in todo}
    public_modules = {obj.__name__ for obj in todo if inspect.ismodule(obj)}  # their pages document their members
    out: dict[str, dict[str, Any]] = {}
    seen: set[Any] = set()
    while todo:
        obj = todo.pop()
        key = obj if isinstance(obj, Constant) else id(obj)
        if key in seen:
            continue
        seen.add(key)
        for target, contexts in references(obj, module_members=id(obj) in public_ids):
            hit = locate(target, contexts)
            if hit is None:
                continue
            dotted, found = _owner(*hit)
            if is_public(dotted, found, alias):
                continue
            if inspect.ismodule(found):
                if found.__name__.startswith(PACKAGE + ".") and found.__name__ not in out:
                    out[found.__name__] = {}
                    todo.append(found)
                continue
            head = dotted.rpartition(".")[0]
            if inspect.isclass(found) or inspect.isroutine(found):
                modname = getattr(found, "__module__", "") or ""
                name = f"{modname}.{found.__qualname__}"
            else:
                modname, name = head, dotted
            if not modname.startswith(PACKAGE + ".") or modname in public_modules or "<" in name \
                    or "._" in name:
                continue  # outside glidectl, documented with a public module, or private
            if modname not in out:  # the module's page shows its docstring: scan it too
                out[modname] = {}
                todo.append(importlib.import_module(modname))
            if name not in out[modname]:
                out[modname][name] = found
                todo.append(Constant(modname, name.rpartition(".")[2]) if object_kind(found) == "data" else found)
    return out


# --- page text ---------------------------------------------------------------------------------------------------

def slug(group: str) -> str:
    """File stem of a group page: ``"flight models and dive records"`` -> ``"flight-models-and-dive-records"``."""
    return re.sub(r"[^a-z0-9]+", "-", group.lower()).strip("-")


def page_stems(names: Iterable[str]) -> dict[str, str]:
    """File stem of each object page, ``glidectl.<name>``; names equal but for case (``Modes``, ``modes``) get a
    ``-<kind>`` suffix so that the pages do not collide on case-insensitive file systems."""
    names = list(names)
    lower = [n.lower() for n in names]
    pkg = importlib.import_module(PACKAGE)
    return {n: f"{PACKAGE}.{n}" + (f"-{object_kind(getattr(pkg, n))}" if lower.count(n.lower()) > 1 else "")
            for n in names}


def heading(text: str, char: str = "=") -> list[str]:
    """A reST title underlined with ``char``."""
    return [text, char * len(text), ""]


def data_doc(name: str, value: Any, modules: Iterable[str] | None = None) -> list[str]:
    """The ``#:`` doc comment of the constant ``name``, read from the first of ``modules`` (default: every glidectl
    module) that holds ``value`` under that name and comments it."""
    for modname in modules if modules is not None else sorted(_package_modules()):
        if getattr(sys.modules.get(modname), name, None) is not value:
            continue
        try:
            docs = ModuleAnalyzer.for_module(modname).find_attr_docs()
        except Exception:  # a module without source: try the next one
            continue
        if ("", name) in docs:
            return [line for line in docs["", name] if line.strip()]
    return []


def data_lines(module: str, name: str, value: Any, doc: list[str]) -> list[str]:
    """A ``py:data`` entry: autodoc's ``autodata`` would show the docstring of the value's type (``tuple``,
    ``dict``) for a constant without a ``#:`` comment, and cannot find the comment of a re-exported one."""
    lines = [f".. py:data:: {name}", f"   :module: {module}"]
    if len(repr(value)) <= VALUE_REPR_MAX:  # a table of specs: its repr would fill the page
        lines.append(f"   :value: {value!r}")
    return [*lines, "", *[f"   {line}" for line in doc], ""]


def _package_modules() -> dict[str, ModuleType]:
    return {k: m for k, m in list(sys.modules.items())
            if m is not None and (k == PACKAGE or k.startswith(PACKAGE + "."))}


GENERATED = f".. generated by docs/_ext/glidectl_api.py from {PACKAGE}.API_GROUPS at build time: do not edit"


def autodoc_lines(name: str, obj: Any) -> list[str]:
    """The directive documenting ``obj`` as ``name`` (relative to the current module, or absolute)."""
    kind = object_kind(obj)
    if kind == "class":
        return [f".. autoclass:: {name}", "   :members:", ""]
    if kind == "exception":
        return [f".. autoexception:: {name}", "   :members:", "   :show-inheritance:", ""]
    if kind == "function":
        return [f".. autofunction:: {name}", ""]
    module, _, short = name.rpartition(".")
    return data_lines(module or PACKAGE, short, obj, data_doc(short, obj, [module] if module else None))


def object_page(name: str, obj: Any, group: str) -> str:
    """reST of the page of ``glidectl.<name>``."""
    lines = [GENERATED, "", *heading(f"{PACKAGE}.{name}")]
    if inspect.ismodule(obj):
        lines += [f".. automodule:: {obj.__name__}", "   :members:", ""]
    else:
        lines += [f".. currentmodule:: {PACKAGE}", "", *autodoc_lines(name, obj)]
    lines += [f"Part of the API group :doc:`{group} <../{slug(group)}>`.", ""]
    if not inspect.ismodule(obj):  # the gallery scripts that use it (sphinx-gallery's backreferences); none: nothing
        lines += [f".. minigallery:: {PACKAGE}.{name}", f"   :add-heading: Examples using ``{PACKAGE}.{name}``", ""]
    return "\n".join(lines)


def group_page(group: str, names: tuple[str, ...], stems: dict[str, str]) -> str:
    """reST of a group page: one autosummary table per kind of object, and the hidden toctree of object pages."""
    pkg = importlib.import_module(PACKAGE)
    lines = [GENERATED, "", f".. _api-{slug(group)}:", "", *heading(group[:1].upper() + group[1:]),
             f".. currentmodule:: {PACKAGE}", ""]
    by_kind: dict[str, list[str]] = {}
    for n in names:
        by_kind.setdefault(object_kind(getattr(pkg, n)), []).append(n)
    for kind, title in SECTIONS:
        members = sorted(by_kind.get(kind, ()), key=str.lower)
        if members:
            lines += [*heading(title, "-"), ".. autosummary::", "   :nosignatures:", ""]
            lines += [f"   {n}" for n in members] + [""]
    lines += [".. toctree::", "   :hidden:", ""]
    lines += [f"   generated/{stems[n]}" for n in sorted(names, key=str.lower)] + [""]
    return "\n".join(lines)


def module_page(modname: str, members: dict[str, Any]) -> str:
    """reST of the page of a non-public module: its docstring and the members docstrings refer to."""
    lines = [GENERATED, "", *heading(modname)]
    lines += [f".. automodule:: {modname}", "   :no-members:", ""]
    if members:
        lines += heading("Members referred to", "-")
    for name, obj in sorted(members.items(), key=lambda kv: kv[0].lower()):
        lines += autodoc_lines(name, obj)
    return "\n".join(lines)


def index_page(groups: dict[str, tuple[str, ...]], modules: Iterable[str]) -> str:
    """reST of the API reference's index: the groups in the order of ``API_GROUPS``, then the modules."""
    lines = [GENERATED, "", ".. _api-reference:", "", *heading("API reference"),
             "``import glidectl as gc`` gives one flat namespace. ``gc.API_GROUPS`` groups it by task; each",
             "group below lists its names, and each name has its own page.", "",
             ".. toctree::", "   :maxdepth: 1", "   :caption: Public API, by task", "",
             "   All names on one page </api>"]
    lines += [f"   {slug(g)}" for g in groups] + [""]
    lines += ["The modules below are not part of the flat namespace; they are documented because the",
              "docstrings above refer to them or to some of their constants and functions.", "",
              ".. toctree::", "   :maxdepth: 1", "   :caption: Modules", ""]
    lines += [f"   modules/{m}" for m in sorted(modules)] + [""]
    return "\n".join(lines)


def _write(path: Path, text: str) -> bool:
    """Write ``text`` to ``path`` unless it already holds it; True when written."""
    if path.exists() and path.read_text(encoding="utf-8") == text:
        return False
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return True


def _home(obj: Any) -> str:
    """The module that defines ``obj`` (a module: itself), where the names of its docstring are meant."""
    return obj.__name__ if inspect.ismodule(obj) else getattr(obj, "__module__", None) or ""


def generate(app: Sphinx) -> None:
    """``builder-inited``: write the API pages and record the defining module of each public page's object."""
    pkg = importlib.import_module(PACKAGE)
    groups: dict[str, tuple[str, ...]] = dict(pkg.API_GROUPS)
    out = Path(app.srcdir) / OUT_DIR
    stems = page_stems(n for names in groups.values() for n in names)
    internal = internal_objects(n for names in groups.values() for n in names)
    pages: dict[Path, str] = {out / "index.rst": index_page(groups, internal)}
    PAGE_HOME.clear()
    for group, names in groups.items():
        pages[out / f"{slug(group)}.rst"] = group_page(group, names, stems)
        for n in names:
            pages[out / "generated" / f"{stems[n]}.rst"] = object_page(n, getattr(pkg, n), group)
            PAGE_HOME[f"{OUT_DIR}/generated/{stems[n]}"] = _home(getattr(pkg, n))
    for modname, members in internal.items():
        pages[out / "modules" / f"{modname}.rst"] = module_page(modname, members)
    written = sum(_write(p, t) for p, t in pages.items())
    for stale in set(out.rglob("*.rst")) - set(pages):
        stale.unlink()
    logger.info("[glidectl_api] %d API pages (%d rewritten), %d modules", len(pages), written, len(internal))


# --- cross-references ---------------------------------------------------------------------------------------------

def _row_contexts(node: nodes.Node) -> list[str]:
    """In an autosummary table, the row's object's class path and defining module (its summary's names are meant
    there); outside a table, nothing."""
    row = node.parent
    while row is not None and not isinstance(row, nodes.row):
        row = row.parent
    if row is None:
        return []
    for ref in row.children[0].findall(nodes.Element):
        name = ref.get("reftarget") or ref.get("reftitle")
        if not name:
            continue
        found, obj = lookup(name)
        if found:
            return [_class_context(obj), _home(obj)]
    return []


def resolve(app: Sphinx, env: BuildEnvironment, node: Any, contnode: nodes.Element) -> nodes.Element | None:
    """``missing-reference``: a ``py`` reference that names a glidectl object as its defining module does."""
    if node.get("refdomain") != "py":
        return None
    target: str = node["reftarget"].lstrip(".~")
    contexts: list[str] = []
    cls_name = node.get("py:class")
    if cls_name:
        found, cls = lookup(f"{node.get('py:module') or PACKAGE}.{cls_name}")
        if found and inspect.isclass(cls):
            contexts.append(_class_context(cls))
    contexts += [PAGE_HOME.get(node.get("refdoc"), ""), *_row_contexts(node), node.get("py:module") or "", PACKAGE]
    contexts = [c for c in dict.fromkeys(contexts) if c]
    if not target.startswith(PACKAGE) and not any(c.startswith(PACKAGE) for c in contexts):
        return None
    hit = locate(target, contexts)
    if hit is None or not (hit[0].startswith(PACKAGE + ".") or hit[0] == PACKAGE):
        return None
    domain = env.get_domain("py")
    for name in documented_names(*hit, aliases()):
        if name == node["reftarget"]:
            continue
        ref = domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"], name, node, contnode)
        if ref is not None:
            return ref
    return None


# --- autosummary's first sentence ---------------------------------------------------------------------------------

def _whole_sentence_summary(original: Callable[[Sequence[str], Any], str]) -> Callable[[Sequence[str], Any], str]:
    """``extract_summary`` that does not cut inside inline markup.

    Autosummary takes a docstring's first sentence, up to the first ``". "``, and means to extend it while that
    cuts an inline literal (``w_i <= a . (X - X_e) + b``); Sphinx 9 checks the whole paragraph instead of the cut
    summary, so a cut literal reaches the page as a docutils warning. This checks the cut summary itself.
    """
    from sphinx.ext import autosummary as asum

    def extract_summary(doc: Sequence[str], settings: Any) -> str:
        summary = original(doc, settings)
        if not any(asum._parse_summary([summary], settings).findall(nodes.system_message)):
            return summary
        text = "\n".join(doc).strip()
        stanza = " ".join(re.split(r"\n\s*\n", text, maxsplit=1)[0].split("\n"))  # the first paragraph
        sentences = asum.periods_re.split(stanza)
        for i in range(1, len(sentences) + 1):
            candidate = ". ".join(sentences[:i]).rstrip(".") + "."
            if not any(asum._parse_summary([candidate], settings).findall(nodes.system_message)):
                return asum.literal_re.sub(".", candidate)
        return summary

    return extract_summary


def _numpydoc_warnings_to_sphinx() -> None:
    """numpydoc reports a docstring it cannot parse (an unknown section, whose text it then drops) with
    ``warnings.warn``, which ``-W`` does not see: log those as Sphinx warnings, so that they fail the build."""
    show = warnings.showwarning
    if getattr(show, "_glidectl", False):
        return

    def showwarning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                    file: Any = None, line: str | None = None) -> None:
        if issubclass(category, UserWarning) and "numpydoc" in filename.replace("\\", "/"):
            logger.warning("numpydoc: %s", message, type="numpydoc")
        else:
            show(message, category, filename, lineno, file, line)

    showwarning._glidectl = True  # type: ignore[attr-defined]
    warnings.showwarning = showwarning


def setup(app: Sphinx) -> dict[str, Any]:
    """Register the page generator and the reference resolver."""
    _numpydoc_warnings_to_sphinx()
    app.setup_extension("sphinx.ext.autosummary")
    from sphinx.ext import autosummary

    internals = ("extract_summary", "_parse_summary", "periods_re", "literal_re")
    if all(hasattr(autosummary, n) for n in internals) and not getattr(autosummary.extract_summary, "_glidectl", 0):
        autosummary.extract_summary = _whole_sentence_summary(autosummary.extract_summary)
        autosummary.extract_summary._glidectl = True  # type: ignore[attr-defined]
    app.connect("builder-inited", generate)
    app.connect("missing-reference", resolve)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True, "env_version": 1}
