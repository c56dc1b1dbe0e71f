"""Table rows of the result types (the rows the design reports print), exact on synthetic results."""

from __future__ import annotations

import numpy as np
import pytest

import glidectl as gc


def _run(stopped_at=None):
    t = np.array([0.0, 1.0, 2.0])
    u = np.array([[3.0, 0.0], [-4.0, 1.0], [0.0, 0.0]])
    err = np.array([[0.0, 0.0], [3.0, 4.0], [0.0, 1.0]])
    return gc.TrackingRun.from_arrays("steady gliding", t, np.zeros((3, 6)), u, err, stopped_at=stopped_at)


def test_tracking_run_row():
    r = _run()
    # trapezoid over [0, 2]: mean of u1^2 = (9/2 + 16 + 0/2) / 2 = 10.25 -> rms 3.2; mean u2^2 = 0.5 -> rms 0.707
    assert r.table_row() == ["steady gliding", "5", "4", "3.2", "1", "0.707", "completed"]
    assert r.table_row("FL")[0] == "FL"
    assert _run(stopped_at=1.5).table_row()[-1] == "stopped at 1.50 s"
    assert len(r.table_row()) == len(gc.TrackingRun.TABLE_HEADER)
    with pytest.raises(gc.ArgumentTypeError, match="label"):
        r.table_row(3)


def test_pareto_rows_mark_the_front():
    rec = {"dt": 0.5, "k3": 10.0, "k4": 5.0, "completed": True, "stopped_at": None, "max_error": 0.12345,
           "effort": 2.0, "peak_u2": 30.0}
    stopped = dict(rec, completed=False, stopped_at=3.21, dt=1.0)
    study = gc.ParetoStudy((rec, stopped), (0,), 8.0)
    assert study.table_rows() == [["0.5", "10", "5", "yes", "0.123", "2", "30", "*"],
                                  ["1", "10", "5", "no (3.2 s)", "0.123", "2", "30", ""]]
    assert len(study.table_rows()[0]) == len(gc.ParetoStudy.TABLE_HEADER)
    with pytest.raises(gc.ArgumentError, match="max_error"):
        gc.ParetoStudy(({"dt": 1.0, "k3": 1.0, "k4": 1.0, "completed": True},), (), 1.0).table_rows()
