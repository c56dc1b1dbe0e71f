"""The naming table of docs/naming.md, checked on every public result type."""

from __future__ import annotations

import dataclasses
import inspect
import typing

import pytest

import glidectl as gc

#: names the table retires (thesis subscripts, old check words)
RETIRED = {"V_e", "gamma_e", "alpha_e", "theta_e", "theta_star", "ratios", "ratios_valid", "ratios_printed",
           "all_valid", "verified", "gram_exact", "exact", "thesis_claim_holds", "condition_holds", "claim_holds",
           "coupling_holds", "theorem3", "holds", "bound_ratio", "worst_ratio"}


def _public_types() -> list[type]:
    seen: dict[str, type] = {}
    todo = [getattr(gc, n) for n in gc.__all__ if inspect.isclass(getattr(gc, n))]
    while todo:
        cls = todo.pop()
        if not inspect.isclass(cls) or not cls.__module__.startswith("glidectl") or cls.__qualname__ in seen:
            continue
        if issubclass(cls, Exception):
            continue
        seen[cls.__qualname__] = cls
        if dataclasses.is_dataclass(cls):  # follow the types its fields hold (e.g. a certificate's verification)
            hints = typing.get_type_hints(cls, include_extras=False) if True else {}
            for h in hints.values():
                todo.extend(a for a in (h, *typing.get_args(h)) if inspect.isclass(a))
        for name, member in inspect.getmembers(cls):
            if name.startswith("_"):
                continue
            ret = getattr(member, "__annotations__", {}).get("return") if callable(member) else None
            if isinstance(ret, str):
                ret = getattr(inspect.getmodule(cls), ret.split("[")[0].strip("'\""), None)
            if inspect.isclass(ret):
                todo.append(ret)
    return sorted(seen.values(), key=lambda c: c.__qualname__)


TYPES = _public_types()


def _fields(cls: type) -> set[str]:
    names = {f.name for f in dataclasses.fields(cls)} if dataclasses.is_dataclass(cls) else set()
    return names | {n for n, v in vars(cls).items() if isinstance(v, property) and not n.startswith("_")}


def test_walk_finds_the_result_types():
    names = {c.__name__ for c in TYPES}
    assert {"SteadyGlide", "Helix", "CTOLGlide", "SingularPerturbation", "CompositeCertificate",
            "CompositeVerification", "ROACertificate", "ROAVerification", "Simulation", "HelixSweep"} <= names


@pytest.mark.parametrize("cls", TYPES, ids=lambda c: c.__qualname__)
def test_result_type_follows_the_naming_table(cls):
    fields = _fields(cls)
    retired = fields & RETIRED
    assert not retired, f"{cls.__qualname__} uses retired names {sorted(retired)} (see docs/naming.md)"
    if dataclasses.is_dataclass(cls):
        hints = typing.get_type_hints(cls)
        if "vehicle" in hints:
            assert hints["vehicle"] in (gc.Vehicle, gc.Vehicle | None), f"{cls.__qualname__}.vehicle must be a Vehicle"
        if "provenance" in hints:
            assert hints["provenance"] is str, f"{cls.__qualname__}.provenance must be a str"
    if "margins" in fields:
        assert "passed" in fields and callable(getattr(cls, "failing", None)), (
            f"{cls.__qualname__} has margins but not passed/failing()")
    summary = getattr(cls, "summary", None)
    if callable(summary):
        ret = typing.get_type_hints(summary).get("return")
        assert ret is str, f"{cls.__qualname__}.summary() must return str"
