#!/usr/bin/env python3
"""Print one TSV line for a run directory: label, integrator, elements, dt, v_s/v_m, centroid x, y,
head, max elevation/a, steps, newton it/step, fallbacks, halvings, wall."""
import json, sys
label, integ, el, dt, d = sys.argv[1:6]
s = json.load(open(d + "/summary.json"))
st = s.get("stats", {})
c = s.get("centroid_displacement", [float("nan")] * 3)
h = s.get("head_final", [float("nan")] * 3)
print("\t".join(str(x) for x in [
    label, integ, el, dt,
    "%.5f" % (s.get("v_s_over_v_m") if s.get("v_s_over_v_m") is not None else float("nan")),
    "%.6f" % c[0], "%.6f" % c[1], "%.6f" % h[0], "%.6f" % h[1],
    "%.3f" % (s.get("max_elevation_over_a") or float("nan")),
    s.get("steps"), "%.2f" % (s.get("newton_iterations_mean") or float("nan")),
    st.get("semismooth_fallbacks"), s.get("step_halvings"),
    "%.1f" % s.get("wall_time_s", float("nan")), s.get("status"), s.get("regime")]))
