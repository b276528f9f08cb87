"""One full-ramp layout row of the validation case gridshell_bh_vs_fe alone (issue 47): the
bar-and-hinge ramp of that layout, judged against the stored FE
(validation/data/gridshell_fe_layouts_full_ramp_level0.json, or its level 1 where
gridshell_fe_layouts_full_ramp_level1.json holds the layout, level 0 then informative, as the case
does) by the case's own function (``validation.cases.gridshell_bh_vs_fe._layout_rows``), without
the rest of the full level.

    OMP_NUM_THREADS=1 python benchmarks/bh_layout_row.py [--layout 5x5]

Prints each metric (value, FE reference, tolerance, passed) and the CPU seconds (one core; the 5 x 5
dome under the rollers: 301 s, 2026-12-07). Not a test.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

from lcefem.validation.cases import gridshell_bh_vs_fe as case


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--layout", default="5x5", help="a layout of the stored full-ramp FE rows")
    a = p.parse_args(argv)
    ref = json.loads(case.FE_LAYOUTS_FULL.read_text())
    fine = {"rows": []}
    if case.FE_LAYOUTS_FULL_FINE.exists():
        fine = json.loads(case.FE_LAYOUTS_FULL_FINE.read_text())
    layouts = sorted({r["layout"] for r in ref["rows"] + fine["rows"]})
    rows = [r for r in fine["rows"] if r["layout"] == a.layout]
    coarse = {
        (r["layout"], r["shape"], r["support"]): (ref, r)
        for r in ref["rows"]
        if r["layout"] == a.layout
    }
    if not rows:  # no level 1: judged against level 0
        rows, fine, coarse = [r for _, r in coarse.values()], ref, {}
    if not rows:
        print(f"--layout = {a.layout!r}: allowed {', '.join(layouts)}", file=sys.stderr)
        return 2
    t0 = time.process_time()
    metrics = case._layout_rows("gridshell_bh_vs_fe", fine, rows, coarse)
    cpu = time.process_time() - t0
    print("metric | BH | FE | tolerance [1/mm] | passed")
    for m in metrics:
        tol = "-" if m.tolerance is None else f"{m.tolerance:g}"
        print(f"{m.metric} | {m.value:.6g} | {m.reference:.6g} | {tol} | {m.passed}")
    print(f"CPU {cpu:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
