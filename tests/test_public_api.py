"""The public API: one flat namespace by task, __all__ everywhere, layers that import downwards only, numpydoc
docstrings (Parameters / Returns / Raises) on every public callable, and the naming table of docs/naming.md."""

from __future__ import annotations

import ast
import importlib
import inspect
import pkgutil
import re
from pathlib import Path

import pytest

import glidectl as gc

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "glidectl"
LOWER = ("models", "trim", "analysis", "stability", "roa")


def _modules() -> list[str]:
    return sorted(m.name for m in pkgutil.walk_packages(gc.__path__, "glidectl."))


def _imports(path: Path) -> list[tuple[str, list[str]]]:
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            mod = node.module or ""
            if node.level:
                pkg = path.relative_to(SRC.parent).with_suffix("").parts[:-node.level]
                mod = ".".join(pkg + ((mod,) if mod else ()))
            out.append((mod, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            out.extend((a.name, []) for a in node.names)
    return out


def test_top_level_is_grouped_by_task_and_complete():
    grouped = {n for names in gc.API_GROUPS.values() for n in names}
    assert grouped == set(gc.__all__)
    assert sum(len(v) for v in gc.API_GROUPS.values()) == len(grouped), "a name is listed in two groups"
    for name in gc.__all__:
        assert hasattr(gc, name), name
    assert not any("central_difference" in n or n.startswith("test") for n in gc.__all__), "no test helpers"


@pytest.mark.parametrize("modname", _modules())
def test_every_module_declares_all(modname):
    mod = importlib.import_module(modname)
    if modname.split(".")[-1].startswith("_") and not modname.endswith("__init__"):
        return  # private helper modules (glidectl._checks) are internal by name
    assert isinstance(getattr(mod, "__all__", None), list | tuple), f"{modname} has no __all__"
    for name in mod.__all__:
        assert hasattr(mod, name), f"{modname}.__all__ names missing {name}"


def test_layers_import_downwards_and_no_private_names_cross_modules():
    bad = []
    for path in sorted(SRC.rglob("*.py")):
        text = path.read_text()
        entry_point = path.name == "cli.py" or path.parts[-2:] == ("report", "designs.py")  # batch builds only
        if re.search(r"matplotlib\.use\(", text) and not entry_point:
            bad.append(f"{path.relative_to(ROOT)} selects a matplotlib backend")
        sub = path.relative_to(SRC).parts[0]
        for mod, names in _imports(path):
            if sub in LOWER and mod.startswith("glidectl.controllers"):
                bad.append(f"{path.relative_to(ROOT)} imports {mod}")
            if mod.startswith("glidectl.studies"):
                bad.append(f"{path.relative_to(ROOT)} imports {mod}")
            private = [n for n in names if n.startswith("_") and not n.startswith("__")]
            if mod.startswith("glidectl") and private and not mod.split(".")[-1].startswith("_"):
                bad.append(f"{path.relative_to(ROOT)} imports private {private} from {mod}")
    assert not bad, "\n".join(bad)


def test_designs_use_only_the_public_api():
    bad = []
    for path in sorted((ROOT / "designs").glob("*.py")):
        for mod, names in _imports(path):
            if not mod.startswith("glidectl"):
                continue
            if mod not in ("glidectl", "glidectl.report") or any(n.startswith("_") for n in names):
                bad.append(f"{path.name}: from {mod} import {names}")
            if mod == "glidectl.report":
                import glidectl.report as rp

                bad.extend(f"{path.name}: glidectl.report.{n} is not public" for n in names if n not in rp.__all__)
    assert not bad, "\n".join(bad)


_SECTION = re.compile(r"^\s*(Parameters|Returns|Raises|Yields|Attributes)\s*\n\s*-{3,}", re.M)


def _sections(obj) -> set[str]:
    return set(_SECTION.findall(inspect.getdoc(obj) or ""))


def _public_callables():
    for name in gc.__all__:
        obj = getattr(gc, name)
        if inspect.ismodule(obj) or not callable(obj):
            continue
        yield name, obj


@pytest.mark.parametrize(("name", "obj"), list(_public_callables()), ids=lambda v: v if isinstance(v, str) else "")
def test_public_callable_has_numpydoc_sections(name, obj):
    doc = inspect.getdoc(obj) or ""
    assert doc, f"{name} has no docstring"
    have = _sections(obj)
    if inspect.isclass(obj) and issubclass(obj, Exception):
        assert issubclass(obj, gc.GlidectlError) and len(doc) > 40, f"{name}: say when it is raised"
        return
    if inspect.isclass(obj):
        assert have & {"Parameters", "Attributes"}, f"{name}: class docstring needs Parameters or Attributes"
        return
    params = [p for p in inspect.signature(obj).parameters if p not in ("self", "cls")]
    need = {"Returns", "Raises"} | ({"Parameters"} if params else set())
    assert need <= have, f"{name}: docstring lacks {sorted(need - have)}"
    # every GlidectlError subclass a docstring lists must exist
    raises = re.split(r"^\s*Raises\s*\n\s*-{3,}", doc, flags=re.M)[1]
    for exc in re.findall(r"^(\w+Error)\b", raises, re.M):
        assert exc in dir(gc) or exc in dir(__builtins__) or hasattr(__import__("builtins"), exc), (name, exc)


def test_docs_api_page_lists_every_public_name_in_its_group():
    text = (ROOT / "docs" / "api.md").read_text()
    sections = dict(re.findall(r"^## ([^\n]+)\n(.*?)(?=^## |\Z)", text, flags=re.M | re.S))
    assert set(sections) == set(gc.API_GROUPS)
    for group, names in gc.API_GROUPS.items():
        listed = set(re.findall(r"^\| `(\w+)` \|", sections[group], flags=re.M))
        assert listed == set(names), (group, sorted(listed ^ set(names)))


def test_docs_stand_alone():
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        text = path.read_text()
        assert "../shared" not in text and "/work/" not in text and "DESIGN.md" not in text, path.name


def _raises_section(doc: str) -> str:
    parts = re.split(r"^\s*Raises\s*\n\s*-{3,}", doc, flags=re.M)
    return re.split(r"^\s*(?:See Also|Notes|Examples|References|Warns)\s*\n\s*-{3,}", parts[1], flags=re.M)[0] \
        if len(parts) > 1 else ""


@pytest.mark.parametrize(("name", "obj"), [(n, o) for n, o in _public_callables() if not inspect.isclass(o)],
                         ids=lambda v: v if isinstance(v, str) else "")
def test_docstring_lists_the_errors_the_function_raises(name, obj):
    """Every glidectl error a public function raises itself (``raise XError(`` in its body) is in its Raises
    section, by name or through a listed base class."""
    try:
        source = inspect.getsource(inspect.unwrap(obj))
    except (OSError, TypeError):
        return
    listed = {getattr(gc, n) for n in re.findall(r"^\s*(\w+Error)\b", _raises_section(inspect.getdoc(obj) or ""),
                                                 re.M) if hasattr(gc, n)}
    raised = {getattr(gc, n) for n in re.findall(r"\braise\s+(\w+Error)\(", source) if hasattr(gc, n)}
    missing = [e.__name__ for e in raised if not any(issubclass(e, lst) for lst in listed)]
    assert not missing, f"{name} raises {missing} but its docstring's Raises section does not list them"
