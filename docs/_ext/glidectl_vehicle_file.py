"""Sphinx extension: the vehicle-file reference's tables, built from glidectl's validation specs.

Every table is built at build time from the objects ``glidectl.load_vehicle`` validates against, so the page cannot
drift from the code:

``glidectl-parameters <kind>``
    The ``[parameters]`` keys of a vehicle kind (:data:`glidectl.params.PARAMETER_SPECS`): unit, constraint,
    required, description; for underwater gliders, the keys only the ``"thesis"`` law reads
    (:data:`glidectl.params.THESIS_LIFT_DRAG_KEYS`) are marked.
``glidectl-hydrodynamics <law>`` (or ``hull``)
    The ``[hydrodynamics]`` keys of one lift and drag law, or the hull and water keys every law accepts
    (:data:`glidectl.params.HYDRO_SPECS`), with the ``gliderflight`` defaults
    (:data:`glidectl.params.GLIDERFLIGHT_DEFAULTS`).
``glidectl-actuators``
    The ``[actuators]`` keys (:data:`glidectl.params.ACTUATOR_SPECS`).
``glidectl-limits``
    The plausibility limits: each constant's value and its ``#:`` doc comment.
``glidectl-presets``
    The presets shipped with glidectl (:func:`glidectl.list_presets`), loaded.
``glidectl-fields <set>``
    A two-column table of the fields of an entry (``vehicle``, ``actuator``, ``uncertainty``, ``moved``); the
    meanings are the directive's content (``name: meaning`` lines), and a field the code accepts without a
    meaning, or a meaning for a field the code does not accept, is a build warning.
``glidectl-docstring-section <module> <title>``
    The body of one section of a module docstring (reST; use it inside ``{eval-rst}`` in a Markdown page).

The first six build docutils nodes directly and work in Markdown (MyST) and reST pages alike.
"""

from __future__ import annotations

import inspect
import math
import re
from collections.abc import Iterable, Sequence
from typing import Any, ClassVar

from docutils import nodes
from docutils.parsers.rst import directives
from docutils.statemachine import StringList
from sphinx.application import Sphinx
from sphinx.pycode import ModuleAnalyzer
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

import glidectl
from glidectl import params, uncertainty

_CONSTRAINT = {"positive": "> 0", "nonnegative": ">= 0", "any": "any"}


# --- node helpers --------------------------------------------------------------------------------------------------

def _cell(content: str | nodes.Node, code: bool = False) -> nodes.entry:
    entry = nodes.entry()
    if isinstance(content, nodes.Node):
        entry += content
    else:
        para = nodes.paragraph()
        para += nodes.literal(content, content) if code and content else nodes.Text(content)
        entry += para
    return entry


def table(header: Sequence[str], rows: Iterable[Sequence[str | nodes.Node]], code_columns: Sequence[int] = (0,),
          widths: Sequence[int] | None = None, classes: Sequence[str] = ()) -> nodes.table:
    """A docutils table; the cells of ``code_columns`` are set as inline code."""
    tbl = nodes.table(classes=["glidectl-spec", *classes])
    group = nodes.tgroup(cols=len(header))
    tbl += group
    for w in widths or [1] * len(header):
        group += nodes.colspec(colwidth=w)
    head = nodes.thead()
    row = nodes.row()
    for h in header:
        row += _cell(h)
    head += row
    group += head
    body = nodes.tbody()
    for values in rows:
        row = nodes.row()
        for i, v in enumerate(values):
            row += _cell(v, code=i in code_columns)
        body += row
    group += body
    return tbl


def _num(value: Any) -> str:
    """A number as a vehicle file would write it (``inf`` spelled out)."""
    if isinstance(value, float) and math.isinf(value):
        return "inf" if value > 0 else "-inf"
    if isinstance(value, tuple):
        return "(" + ", ".join(_num(v) for v in value) + ")"
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def _spec_rows(spec: dict[str, params.ParamSpec], note: dict[str, str] | None = None,
               defaults: dict[str, float] | None = None) -> list[list[str]]:
    rows = []
    for key, s in spec.items():
        row = [key, s.unit, _CONSTRAINT.get(s.constraint, s.constraint), "yes" if s.required else ""]
        if defaults is not None:
            row.append(_num(defaults[key]) if key in defaults else "")
        row.append(s.description + (f" ({note[key]})" if note and key in note else ""))
        rows.append(row)
    return rows


# --- directives ----------------------------------------------------------------------------------------------------

class ParametersTable(SphinxDirective):
    """``[parameters]`` keys of one vehicle kind."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        kind = self.arguments[0]
        if kind not in params.PARAMETER_SPECS:
            raise self.error(f"unknown vehicle kind {kind!r}; known: {', '.join(params.PARAMETER_SPECS)}")
        note = {k: "thesis law only" for k in params.THESIS_LIFT_DRAG_KEYS} if kind == "underwater_glider" else {}
        rows = _spec_rows(dict(params.PARAMETER_SPECS[kind]), note)
        return [table(["key", "unit", "sign", "required", "description"], rows, (0, 1), (14, 14, 7, 8, 57))]


class HydrodynamicsTable(SphinxDirective):
    """``[hydrodynamics]`` keys of one law, or (argument ``hull``) the hull and water keys of every law."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        arg = self.arguments[0]
        hull = _hull_keys()
        if arg == "hull":
            spec = {k: params.HYDRO_SPECS["thesis"][k] for k in hull}
        elif arg in params.HYDRO_SPECS:
            spec = {k: s for k, s in params.HYDRO_SPECS[arg].items() if k not in hull}
        else:
            raise self.error(f"unknown law {arg!r}; known: hull, {', '.join(params.HYDRO_SPECS)}")
        if not spec:
            return [nodes.paragraph(text="No keys of its own.")]
        defaults = dict(params.GLIDERFLIGHT_DEFAULTS) if arg == "gliderflight" else None
        header = ["key", "unit", "sign", "required", *(["default"] if defaults is not None else []), "description"]
        widths = (12, 12, 7, 8, *((9,) if defaults is not None else ()), 52)
        return [table(header, _spec_rows(spec, defaults=defaults), (0, 1), widths)]


def _hull_keys() -> list[str]:
    """The keys every law accepts (the hull and water keys), in the order of the ``thesis`` law."""
    laws = list(params.HYDRO_SPECS.values())
    return [k for k in laws[0] if all(k in law for law in laws)]


class ActuatorsTable(SphinxDirective):
    """``[actuators]`` keys."""

    def run(self) -> list[nodes.Node]:
        rows = [[name, s.unit, f"{s.unit}/s", s.description] for name, s in params.ACTUATOR_SPECS.items()]
        return [table(["key", "unit of min, max, fixed", "unit of rate", "description"], rows, (0, 1, 2),
                      (10, 12, 12, 66))]


#: the plausibility limits and defaults shown by ``glidectl-limits``: (module, constant name)
LIMITS = (
    (params, "MAX_FILE_BYTES"), (params, "VALUE_MAX"), (params, "POSITIVE_MIN"), (params, "PUMP_FRACTION_MAX"),
    (params, "HULL_MASS_RATIO"), (params, "DENSITY_RANGE"), (params, "DEFAULT_DENSITY"),
    (uncertainty, "CORRELATION_TOL"), (uncertainty, "VERTEX_STDS"), (uncertainty, "MAX_REJECTIONS"),
)


def attr_doc(module: Any, name: str) -> str:
    """The ``#:`` doc comment of ``module.name`` as one line (empty when there is none)."""
    docs = ModuleAnalyzer.for_module(module.__name__).find_attr_docs()
    return " ".join(line.strip() for line in docs.get(("", name), []) if line.strip())


class LimitsTable(SphinxDirective):
    """The plausibility limits a vehicle file is checked against."""

    def run(self) -> list[nodes.Node]:
        rows = []
        for module, name in LIMITS:
            rows.append([f"{module.__name__}.{name}", _num(getattr(module, name)),
                         _rst_to_text(attr_doc(module, name))])
        return [table(["constant", "value", "meaning"], rows, (0, 1), (30, 14, 56))]


def _rst_to_text(text: str) -> str:
    """Inline reST roles and double backquotes reduced to plain text (``:data:`X``` -> ``X``)."""
    text = re.sub(r":[a-z:]+:`~?([^`]+)`", r"\1", text)
    return text.replace("``", "")


class PresetsTable(SphinxDirective):
    """The presets shipped with glidectl, loaded (so a preset that does not load fails the build)."""

    def run(self) -> list[nodes.Node]:
        rows = []
        for name in glidectl.list_presets():
            v = glidectl.load_vehicle(name)
            acts = ", ".join(f"{k} (fixed)" if a.fixed is not None else k for k, a in v.actuators.items())
            rows.append([name, v.kind, v.law, v.title, acts or "none", ", ".join(v.uncertainty) or "none"])
        return [table(["preset", "kind", "law", "title", "actuators", "uncertainty"], rows, (0, 1, 2),
                      (14, 14, 9, 37, 16, 10))]


def _ordered(fields: Iterable[str], preferred: Sequence[str]) -> list[str]:
    """``fields`` (a set) in the ``preferred`` order, fields not in it after, alphabetically."""
    fields = set(fields)
    return [f for f in preferred if f in fields] + sorted(fields - set(preferred))


def _field_sets() -> dict[str, tuple[list[str], str]]:
    """The field sets ``glidectl-fields`` documents: name -> (fields in the code's order, where they come from)."""
    return {
        "vehicle": (_ordered(params._HEADER_KEYS, ("name", "kind", "title", "source", "notes")),
                    "glidectl.params._HEADER_KEYS"),
        "actuator": (_ordered(params._ACTUATOR_FIELDS, ("min", "max", "rate", "fixed", "unit", "source", "note")),
                     "glidectl.params._ACTUATOR_FIELDS"),
        "uncertainty": (list(uncertainty.UNCERTAINTY_FIELDS), "glidectl.uncertainty.UNCERTAINTY_FIELDS"),
        "moved": (list(params._MOVED_KEYS), "glidectl.params._MOVED_KEYS"),
    }


class FieldsTable(SphinxDirective):
    """Fields of an entry, with meanings from the directive's content, checked against the code's field set."""

    required_arguments = 1
    has_content = True
    option_spec: ClassVar[dict[str, Any]] = {"header": directives.unchanged}

    def run(self) -> list[nodes.Node]:
        sets = _field_sets()
        which = self.arguments[0]
        if which not in sets:
            raise self.error(f"unknown field set {which!r}; known: {', '.join(sets)}")
        fields, origin = sets[which]
        meaning: dict[str, str] = {}
        for line in self.content:
            if not line.strip():
                continue
            key, sep, text = line.partition(":")
            if not sep:
                raise self.error(f"expected 'field: meaning', got {line!r}")
            meaning[key.strip().strip("`")] = text.strip()
        out: list[nodes.Node] = []
        for f in fields:
            if f not in meaning:
                out.append(self.state.document.reporter.warning(
                    f"glidectl-fields {which}: field {f!r} of {origin} has no meaning in the page", line=self.lineno))
        for f in meaning:
            if f not in fields:
                out.append(self.state.document.reporter.warning(
                    f"glidectl-fields {which}: {f!r} is not a field of {origin} (the code accepts "
                    f"{', '.join(fields)})", line=self.lineno))
        header = (self.options.get("header") or "field, meaning").split(",")
        if which == "moved":
            rows = [[f, params._MOVED_KEYS[f], self._inline(meaning.get(f, ""))] for f in fields]
            return [table(["old key", "write instead, in [actuators]", header[-1].strip()], rows, (0, 1),
                          (10, 50, 40)), *out]
        rows = [[f, self._inline(meaning.get(f, ""))] for f in fields]
        return [table([h.strip() for h in header], rows, (0,), (15, 85)), *out]

    def _inline(self, text: str) -> nodes.paragraph:
        """``text`` parsed as inline markup of the page (Markdown in a MyST page, reST in a reST page)."""
        para = nodes.paragraph()
        children, messages = self.state.inline_text(text, self.lineno)
        para.extend(children)
        para.extend(messages)
        return para


class DocstringSection(SphinxDirective):
    """The body of section ``title`` of a module's docstring, parsed as reST (use inside ``{eval-rst}``)."""

    required_arguments = 2
    final_argument_whitespace = True

    def run(self) -> list[nodes.Node]:
        modname, title = self.arguments[0], self.arguments[1].strip().strip('"')
        module = __import__(modname, fromlist=["_"])
        doc = inspect.cleandoc(module.__doc__ or "").splitlines()
        start = None
        for i in range(len(doc) - 1):
            if doc[i].strip() == title and re.fullmatch(r"-{3,}", doc[i + 1].strip()):
                start = i + 2
                break
        if start is None:
            raise self.error(f"{modname} has no docstring section {title!r}")
        end = len(doc)
        for i in range(start, len(doc) - 1):
            if doc[i].strip() and re.fullmatch(r"-{3,}", doc[i + 1].strip()):
                end = i
                break
        container = nodes.container(classes=["glidectl-docstring"])
        body = StringList(doc[start:end], source=f"docstring of {modname}")
        with _current_module(self, modname):
            nested_parse_with_titles(self.state, body, container)
        return [container]


class _current_module:
    """Resolve the section's cross-references in ``modname``, as they were written."""

    def __init__(self, directive: SphinxDirective, modname: str) -> None:
        self.ref_context = directive.env.ref_context
        self.modname = modname
        self.saved: Any = None

    def __enter__(self) -> None:
        self.saved = self.ref_context.get("py:module")
        self.ref_context["py:module"] = self.modname

    def __exit__(self, *exc: object) -> None:
        if self.saved is None:
            self.ref_context.pop("py:module", None)
        else:
            self.ref_context["py:module"] = self.saved


def setup(app: Sphinx) -> dict[str, Any]:
    """Register the directives."""
    app.add_directive("glidectl-parameters", ParametersTable)
    app.add_directive("glidectl-hydrodynamics", HydrodynamicsTable)
    app.add_directive("glidectl-actuators", ActuatorsTable)
    app.add_directive("glidectl-limits", LimitsTable)
    app.add_directive("glidectl-presets", PresetsTable)
    app.add_directive("glidectl-fields", FieldsTable)
    app.add_directive("glidectl-docstring-section", DocstringSection)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
