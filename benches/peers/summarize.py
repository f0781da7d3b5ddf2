#!/usr/bin/env python3
"""Summarize OUT/<scene>.csv: for each scene and method, the least CPU time of a point
whose error is at or below the target (position group, or reaction where the scene has one;
a scene's score is the larger of its groups), and the same interpolated log-log between
the two points around the target.
    summarize.py [OUT] [--target scene=err ...]"""
import csv
import math
import os
import sys

TARGETS = {"a01_pendulum": 1e-6, "chain_n100": 1e-7, "impact_block_k1e5": 1e-6,
           "impact_block_k1e7": 1e-6, "slider_crank_driven": 1e-6}


def err_of(r):
    es = [float(r[k]) for k in ("error_position", "error_reaction") if r[k] not in ("", None)]
    return max(es) if es else None


def main():
    args = sys.argv[1:]
    out = args[0] if args and not args[0].startswith("--") else os.path.join(
        os.path.dirname(__file__), "..", "..", "target", "peers")
    for a in args:
        if "=" in a:
            s, v = a.split("=", 1)
            TARGETS[s.lstrip("-")] = float(v)
    print("| scene | target | method | formulation | best setting ≤ target | error | CPU s | interpolated CPU s at target |")
    print("|---|---|---|---|---|---|---|---|")
    for scene, tgt in TARGETS.items():
        path = os.path.join(out, scene + ".csv")
        if not os.path.exists(path):
            continue
        rows = [r for r in csv.DictReader(open(path)) if r["status"] == "ok" and err_of(r) is not None]
        groups = {}
        for r in rows:
            groups.setdefault((r["method"], r["formulation"]), []).append(r)
        res = []
        for (m, f), rs in groups.items():
            ok = [r for r in rs if err_of(r) <= tgt]
            if not ok:
                res.append((math.inf, m, f, "-", "-", "-", "-"))
                continue
            b = min(ok, key=lambda r: float(r["cpu_s"]))
            # interpolate between the cheapest point at/below target and the best point above it
            above = [r for r in rs if err_of(r) > tgt and float(r["cpu_s"]) < float(b["cpu_s"])]
            interp = float(b["cpu_s"])
            if above:
                a = max(above, key=lambda r: float(r["cpu_s"]))
                e1, c1, e2, c2 = err_of(a), float(a["cpu_s"]), err_of(b), float(b["cpu_s"])
                if e1 > e2 > 0:
                    w = (math.log(tgt) - math.log(e1)) / (math.log(e2) - math.log(e1))
                    interp = math.exp(math.log(c1) + w * (math.log(c2) - math.log(c1)))
            res.append((interp, m, f, b["setting"], err_of(b), float(b["cpu_s"]), interp))
        for interp, m, f, s, e, c, i in sorted(res):
            if s == "-":
                print("| %s | %g | %s | %s | not reached | | | |" % (scene, tgt, m, f))
            else:
                print("| %s | %g | %s | %s | %s | %.2e | %.3g | %.3g |" % (scene, tgt, m, f, s, e, c, i))


if __name__ == "__main__":
    main()
