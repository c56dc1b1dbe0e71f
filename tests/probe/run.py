"""Probe of glidectl's public API: every case of ``cases.py`` in its own process, time- and memory-capped.

Usage::

    python tests/probe/run.py [--src DIR] [--jobs 2] [--timeout 30] [--mem-gb 4] [--only ID_OR_PREFIX ...]
                              [--group NAME ...] [--out results.json] [--resume] [--list]

``--src DIR`` puts ``DIR`` first on the children's ``PYTHONPATH`` so that another checkout (its ``src`` folder) is
probed. Each child prints ``@@READY@@`` once its imports and prelude are done (the wall-time cap starts then) and
one line ``@@PROBE@@ {json}`` with what happened; the parent classifies it:

- ``clear_error``: a GlidectlError subclass was raised where an error is expected (or allowed);
- ``right``: a value was returned where one is expected (or allowed) and the case's check holds;
- ``traceback``: any other exception escaped (MemoryError and RecursionError included);
- ``silent_wrong``: a value was returned where an error is expected, or the check failed or the value is not finite;
- ``refused``: a GlidectlError where a right answer is expected (a valid call refused: a regression);
- ``hang``: the wall-time cap (or the case's own ``limit``) was hit;
- ``crash``: the process died without reporting (segfault, killed at the memory cap, ...).

Exit status: 0 when every case is clean (``clear_error`` or ``right``), 1 otherwise, 2 on a usage error.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import signal
import subprocess
import sys
import threading
import time
import traceback
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
MARK = "@@PROBE@@ "
READY = "@@READY@@"
CLASSES = ("clear_error", "right", "traceback", "silent_wrong", "refused", "hang", "crash")
CLEAN = ("clear_error", "right")


def _one_line(text: str, n: int = 300) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= n else text[: n - 3] + "..."


# ------------------------------------------------------------------------------------------------ child side
def _is_finite_plain(r: Any) -> bool | None:
    """Finiteness of a plain numeric result (number, numeric array, list/tuple of numbers); None for others."""
    import numpy as np

    if isinstance(r, bool):
        return None
    if isinstance(r, int | float | complex | np.number | np.ndarray) or (
            isinstance(r, list | tuple) and r and all(isinstance(x, int | float | complex | np.number) for x in r)):
        a = np.asarray(r)
        if a.dtype.kind in "iufc":
            return bool(np.all(np.isfinite(a)))
    return None


def _where(exc: BaseException) -> str:
    """``file:line in function`` of the innermost glidectl frame of ``exc`` (else the innermost frame)."""
    frames = traceback.extract_tb(exc.__traceback__)
    if not frames:
        return ""
    inner = [f for f in frames if "glidectl" in f.filename] or frames
    f = inner[-1]
    return f"{Path(f.filename).name}:{f.lineno} in {f.name}"


def child(case_id: str, mem_gb: float) -> int:
    """Run one case in this process and print one ``@@PROBE@@`` JSON line on the original stdout."""
    out_fd = os.dup(1)
    os.dup2(2, 1)  # whatever the snippet prints (also from C) goes to stderr
    sys.stdout = sys.stderr
    if mem_gb > 0:
        import resource

        cap = int(mem_gb * 2**30)
        resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
    report: dict[str, Any] = {"id": case_id}

    def emit() -> int:
        os.write(out_fd, (MARK + json.dumps(report, default=str) + "\n").encode())
        return 0

    sys.path.insert(0, str(HERE))
    import cases as C  # tests/probe/cases.py

    case = next((k for k in C.CASES if k.id == case_id), None)
    if case is None:
        report.update(status="internal", message=f"no case {case_id}")
        return emit()
    ns: dict[str, Any] = {"__name__": "__probe__", **C.HELPERS}
    try:
        exec(compile(C.PRELUDE, "<prelude>", "exec"), ns)
        import glidectl

        report["glidectl"] = str(Path(glidectl.__file__).resolve().parent)
        C.STATE["tmp"] = ns["TMP"]
        os.write(out_fd, (READY + "\n").encode())  # the parent's wall-time cap starts now (imports are slow)
    except BaseException as exc:
        report.update(status="prelude", exc_type=type(exc).__name__, message=f"{exc} ({_where(exc)})")
        return emit()
    base = glidectl.GlidectlError
    try:
        try:
            code = compile(case.code, f"<{case.id}>", "eval")
            single = True
        except SyntaxError:
            code = compile(case.code, f"<{case.id}>", "exec")
            single = False
        t0 = time.perf_counter()
        try:
            if single:
                r = eval(code, ns)
            else:
                exec(code, ns)
                r = ns.get("r")
        except BaseException as exc:  # MemoryError, RecursionError, SystemExit... all count
            report["elapsed"] = time.perf_counter() - t0
            report.update(status="raised", glidectl_error=isinstance(exc, base), exc_type=type(exc).__name__,
                          mro=[k.__name__ for k in type(exc).__mro__], message=str(exc), where=_where(exc))
            return emit()
        report["elapsed"] = elapsed = time.perf_counter() - t0
        report.update(status="returned", result_type=type(r).__name__)
        try:
            report["result"] = _one_line(repr(r), 200)
        except Exception as exc:
            report["result"] = f"<repr failed: {type(exc).__name__}>"
        report["plain_finite"] = _is_finite_plain(r)
        if case.check is not None:
            ns["r"], ns["elapsed"] = r, elapsed
            try:
                report["check"] = bool(eval(compile(case.check, f"<{case.id} check>", "eval"), ns))
            except BaseException as exc:
                report["check"] = False
                report["check_error"] = f"{type(exc).__name__}: {exc} ({_where(exc)})"
        return emit()
    finally:
        if ns.get("TMP"):
            import shutil

            shutil.rmtree(str(ns["TMP"]), ignore_errors=True)


# ----------------------------------------------------------------------------------------------- parent side
def classify(case: Any, rep: dict[str, Any] | None, *, returncode: int | None, timed_out: str | None,
             stderr_tail: str) -> tuple[str, str]:
    """(class, one-line message) of one case; ``timed_out`` is the hang message when a cap was hit."""
    if timed_out:
        return "hang", timed_out
    if rep is None:
        sig = ""
        if returncode is not None and returncode < 0:
            try:
                sig = f" ({signal.Signals(-returncode).name})"
            except ValueError:
                sig = ""
        tail = _one_line(stderr_tail.strip().splitlines()[-1] if stderr_tail.strip() else "", 200)
        return "crash", f"process died, exit status {returncode}{sig}, no report; {tail}"
    status = rep.get("status")
    if status in ("prelude", "internal"):
        return "traceback", _one_line(f"{status}: {rep.get('exc_type', '')}: {rep.get('message', '')}")
    elapsed = float(rep.get("elapsed", 0.0))
    if case.limit is not None and elapsed > case.limit:
        what = rep.get("exc_type") if status == "raised" else "a value"
        return "hang", f"took {elapsed:.1f} s (limit {case.limit:g} s) before giving {what}"
    if status == "raised":
        msg = _one_line(f"{rep['exc_type']}: {rep.get('message', '')}")
        if rep.get("glidectl_error"):
            return ("refused", msg) if case.expect == "ok" else ("clear_error", msg)
        return "traceback", _one_line(f"{msg} [{rep.get('where', '')}]")
    # returned
    got = rep.get("result", "")
    if case.expect == "error":
        return "silent_wrong", _one_line(f"returned {got} (a GlidectlError was expected)")
    if rep.get("plain_finite") is False:
        return "silent_wrong", _one_line(f"returned non-finite {got}")
    if not rep.get("check", False):
        why = f"check raised {rep['check_error']}" if rep.get("check_error") else f"check failed: {case.check}"
        return "silent_wrong", _one_line(f"{why}; returned {got}")
    return "right", _one_line(f"returned {got}", 160)


def run_case(case: Any, args: argparse.Namespace, env: dict[str, str]) -> dict[str, Any]:
    """Run one case in a child process; the wall-time cap counts from the end of its imports and prelude."""
    cmd = [sys.executable, str(Path(__file__).resolve()), "--child", case.id, "--mem-gb", str(args.mem_gb)]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, cwd=args.cwd,
                            start_new_session=True)
    ready = threading.Event()
    out_lines: list[str] = []
    err_chunks: list[bytes] = []

    def read_out() -> None:
        assert proc.stdout is not None
        for raw in proc.stdout:
            line = raw.decode(errors="replace")
            out_lines.append(line)
            if line.startswith(READY):
                ready.set()
        ready.set()  # end of output: the child is gone

    def read_err() -> None:
        assert proc.stderr is not None
        for raw in proc.stderr:
            err_chunks.append(raw)
            if len(err_chunks) > 400:
                del err_chunks[:200]

    readers = [threading.Thread(target=read_out, daemon=True), threading.Thread(target=read_err, daemon=True)]
    for t in readers:
        t.start()
    timed_out: str | None = None
    cap = max(args.timeout, case.timeout or 0.0)
    if not ready.wait(timeout=args.startup):
        timed_out = f"imports and prelude not done within {args.startup:g} s"
    else:
        try:
            proc.wait(timeout=cap)
        except subprocess.TimeoutExpired:
            timed_out = f"no result within the {cap:g} s wall-time cap (counted after imports and prelude)"
    if timed_out:
        try:
            os.killpg(proc.pid, signal.SIGKILL)  # the child and anything it started (its own session)
        except ProcessLookupError:
            pass
    proc.wait()
    for t in readers:
        t.join(timeout=10)
    wall = time.perf_counter() - t0
    rep = None
    for line in "".join(out_lines).splitlines():
        if line.startswith(MARK):
            try:
                rep = json.loads(line[len(MARK):])
            except json.JSONDecodeError:
                rep = None
    stderr = b"".join(err_chunks).decode(errors="replace")
    cls, msg = classify(case, rep, returncode=proc.returncode, timed_out=timed_out, stderr_tail=stderr[-2000:])
    row = {"id": case.id, "group": case.group, "expect": case.expect, "class": cls, "message": msg,
           "wall": round(wall, 2), "code": case.code, "check": case.check, "limit": case.limit, "note": case.note}
    if rep is not None:
        row.update({k: rep[k] for k in ("exc_type", "where", "elapsed", "result", "glidectl") if k in rep})
    return row


def _table(rows: list[dict[str, Any]], groups: tuple[str, ...]) -> str:
    by = {gname: Counter(r["class"] for r in rows if r["group"] == gname) for gname in groups}
    total = Counter(r["class"] for r in rows)
    width = max(len(gname) for gname in (*groups, "total")) + 2
    head = "group".ljust(width) + "".join(f"{k:>13}" for k in CLASSES) + f"{'cases':>8}"
    lines = [head, "-" * len(head)]
    for gname in groups:
        n = sum(by[gname].values())
        if n:
            lines.append(gname.ljust(width) + "".join(f"{by[gname][k]:>13}" for k in CLASSES) + f"{n:>8}")
    lines.append("-" * len(head))
    lines.append("total".ljust(width) + "".join(f"{total[k]:>13}" for k in CLASSES) + f"{len(rows):>8}")
    return "\n".join(lines)


def _git_commit(src: Path) -> str | None:
    """Short commit of the checkout holding ``src`` (read-only git commands), with "(modified)" when dirty."""
    try:
        out = subprocess.run(["git", "-C", str(src), "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                             timeout=10)
        dirty = subprocess.run(["git", "-C", str(src), "status", "--porcelain", "--untracked-files=no", "."],
                               capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    if out.returncode:
        return None
    return out.stdout.strip() + (" (modified)" if dirty.stdout.strip() else "")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--src", help="folder put first on PYTHONPATH (e.g. /path/to/checkout/src)")
    p.add_argument("--jobs", type=int, default=2, help="cases run at once (default 2)")
    p.add_argument("--timeout", type=float, default=30.0,
                   help="wall-time cap per case in seconds, counted after its imports and prelude (default 30)")
    p.add_argument("--startup", type=float, default=180.0,
                   help="cap in seconds on a child's imports and prelude, before --timeout starts (default 180)")
    p.add_argument("--mem-gb", type=float, default=4.0, help="address-space cap per case in GiB (default 4; 0: none)")
    p.add_argument("--only", nargs="+", metavar="ID", help="case ids or id prefixes (e.g. trim.helix)")
    p.add_argument("--group", nargs="+", help="only these groups")
    p.add_argument("--out", default="results.json", help="results JSON (default ./results.json)")
    p.add_argument("--resume", action="store_true",
                   help="keep the rows of --out whose case (id, code, check) is unchanged and run only the others")
    p.add_argument("--list", action="store_true", help="list the cases and exit")
    p.add_argument("--child", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.child:
        return child(args.child, args.mem_gb)

    sys.path.insert(0, str(HERE))
    import cases as C

    selected = list(C.CASES)
    if args.only:
        selected = [k for k in selected if any(k.id == o or k.id.startswith(o.rstrip(".") + ".") for o in args.only)]
    if args.group:
        selected = [k for k in selected if k.group in args.group]
    if args.list:
        for k in selected:
            print(f"{k.id:<48} {k.group:<28} {k.expect:<7} {k.code.splitlines()[0][:80]}")
        print(f"{len(selected)} cases")
        return 0
    if not selected:
        print("no case selected", file=sys.stderr)
        return 2
    env = dict(os.environ)
    env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1", MPLBACKEND="Agg",
               PYTHONDONTWRITEBYTECODE="1", PYTHONHASHSEED="0")
    src = None
    if args.src:
        src = Path(args.src).resolve()
        if not (src / "glidectl" / "__init__.py").exists():
            print(f"--src {src}: no glidectl package there", file=sys.stderr)
            return 2
        env["PYTHONPATH"] = str(src) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    args.cwd = str(Path.cwd())
    probe = subprocess.run([sys.executable, "-c", "import glidectl, pathlib; "
                            "print(pathlib.Path(glidectl.__file__).resolve().parent)"],
                           capture_output=True, text=True, env=env, timeout=300)
    where = probe.stdout.strip() or f"(cannot import glidectl: {_one_line(probe.stderr, 200)})"
    commit = _git_commit(Path(where)) if probe.returncode == 0 else None
    print(f"probing {where}" + (f" at {commit}" if commit else "") +
          f": {len(selected)} cases, {args.jobs} jobs, {args.timeout:g} s and {args.mem_gb:g} GiB per case",
          flush=True)
    out = Path(args.out)
    done: dict[str, dict[str, Any]] = {}
    if args.resume and out.exists():
        try:
            old = json.loads(out.read_text()).get("results", [])
        except (OSError, json.JSONDecodeError):
            old = []
        same = {k.id: (k.code, k.check) for k in selected}
        done = {r["id"]: r for r in old if same.get(r.get("id")) == (r.get("code"), r.get("check"))}
        print(f"resuming: {len(done)} case(s) kept from {out}", flush=True)
    t0 = time.time()
    order = {k.id: i for i, k in enumerate(selected)}
    rows: list[dict[str, Any]] = [done[k.id] for k in selected if k.id in done]
    todo = [k for k in selected if k.id not in done]
    width = max(len(k.id) for k in selected)
    meta = {"glidectl": where, "commit": commit, "src": str(src) if src else None, "jobs": args.jobs,
            "timeout": args.timeout, "mem_gb": args.mem_gb, "python": platform.python_version(),
            "started": time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(t0))}

    def save(complete: bool) -> None:
        counts = Counter(r["class"] for r in rows)
        result = {
            "meta": {**meta, "cases": len(rows), "complete": complete, "duration_s": round(time.time() - t0, 1)},
            "counts": {k: counts[k] for k in CLASSES},
            "by_group": {gname: {k: sum(1 for r in rows if r["group"] == gname and r["class"] == k) for k in CLASSES}
                         for gname in C.GROUPS},
            "results": sorted(rows, key=lambda r: order.get(r["id"], len(order))),
        }
        out.parent.mkdir(parents=True, exist_ok=True)
        part = out.with_name(out.name + ".part")
        part.write_text(json.dumps(result, indent=1))
        part.replace(out)  # a run that is stopped leaves the rows done so far (rerun with --resume)

    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = [pool.submit(run_case, k, args, env) for k in todo]
        for i, fut in enumerate(futures, 1):
            row = fut.result()
            rows.append(row)
            save(False)
            print(f"[{i:3d}/{len(todo)}] {row['id']:<{width}} {row['class']:<12} {row['wall']:6.1f} s  "
                  f"{row['message'][:90]}", flush=True)
    rows.sort(key=lambda r: order.get(r["id"], len(order)))
    save(True)
    duration = time.time() - t0
    print()
    print(_table(rows, C.GROUPS))
    bad = [r for r in rows if r["class"] not in CLEAN]
    if bad:
        print(f"\n{len(bad)} non-clean case(s):")
        for cls in CLASSES:
            for r in bad:
                if r["class"] == cls:
                    print(f"  {cls:<12} {r['id']:<{width}}  {r['message']}")
    print(f"\n{len(rows)} cases in {duration:.0f} s; results in {out}")
    return 0 if not bad else 1


if __name__ == "__main__":
    sys.exit(main())
