"""Reproduce the paper's Table: E_min, E_max and gain for rectangles W x 2W, W = 20 ... 80 mm.

Runs the least- and most-energy placement searches of the Orthoglide for the seven rectangles of
Ur-Rehman et al. (groove milling at 0.66 m/s, x, y, z, phi free), for every regeneration mode
with the paper's timing law, and with the realistic timing law, and writes a Markdown report with
our numbers beside the paper's.

Usage: python examples/paper_table.py [--out docs/paper_table.md] [--time-step S] [--workers N] [--json FILE]
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

PAPER = {20: (15.26, 44.46, 65.68), 30: (22.88, 61.35, 62.71), 40: (30.41, 76.31, 60.15), 50: (38.55, 89.80, 57.07),
         60: (46.83, 102.11, 54.13), 70: (56.82, 113.46, 49.92), 80: (65.94, 121.17, 46.89)}
WIDTHS_MM = sorted(PAPER)
CASES = [("paper", mode) for mode in ("clip", "bus", "signed", "absolute")] + [("realistic", "clip")]
EXAMPLE = Path(__file__).with_name("rect.yaml")
Q_MINUS_M = -0.12679491924311226
CALIBRATION_MARKER = "<!-- paper_calibration.py writes what follows -->"


def rectangle(width_mm: int, timing: str = "paper"):
    """The paper's W x 2W rectangle (examples/rect.yaml resized) with the given timing law."""
    from placement.path import load_path

    text = EXAMPLE.read_text().replace("width: 30, length: 60", f"width: {width_mm}, length: {2 * width_mm}")
    with tempfile.TemporaryDirectory() as folder:  # paths are files: write the resized one
        file = Path(folder) / "rect.yaml"
        file.write_text(text.replace("mode: paper", f"mode: {timing}"))
        return load_path(file)


@functools.cache
def orthoglide():
    """The robot, loaded once per worker process."""
    from placement import load_robot

    return load_robot("orthoglide")


def run_group(width_mm: int, timing: str, modes: tuple[str, ...], time_step_s: float) -> list[dict]:
    """Both searches for one rectangle and timing law, for each regeneration mode, the modes sharing the chain
    (runs in a worker, on one thread: the workers share the cores)."""
    from regeneration_modes import optimize_modes  # beside this file

    from placement.evaluation.evaluator import EvaluatorSettings

    path = rectangle(width_mm, timing)
    results = optimize_modes(orthoglide(), path, modes,
                             evaluation=EvaluatorSettings(time_step_s=time_step_s, threads=1))
    return [case(width_mm, timing, mode, result) for mode, result in results.items()]


def case(width_mm: int, timing: str, regeneration: str, result) -> dict:
    """One case's numbers: the optima's energies, re-checks and placements, and the gain."""
    out = {"width": width_mm, "timing": timing, "regeneration": regeneration, "gain": result.gain,
           "infeasible": result.infeasible}
    for key, optimum in (("min", result.best), ("max", result.worst)):
        out[key] = None if optimum is None else {
            "energy": float(optimum.detail.energy.total_J), "recheck": optimum.recheck_value,
            "placement": optimum.detail.placement.tolist(),
            "lowest_corner": optimum.detail.tool_position_m.min(axis=0).tolist()}  # of the path's bounding box
    return out


def location(placement: list[float]) -> str:
    x, y, z, phi = (round(v, 0) + 0.0 for v in (*np.multiply(placement[:3], 1e3), np.degrees(placement[3])))
    return f"({x:.0f}, {y:.0f}, {z:.0f}) mm, {phi:.0f}°"


def table(results: list[dict], timing: str, regeneration: str) -> list[str]:
    lines = ["| W × L mm | E_min J (paper) | E_max J (paper) | gain % (paper) | E_min at (x, y, z), φ | E_max at (x, y, z), φ | "
             "densest re-check |",
             "|---|---|---|---|---|---|---|"]
    for r in sorted((r for r in results if r["timing"] == timing and r["regeneration"] == regeneration),
                    key=lambda r: r["width"]):
        e_min, e_max, gain = PAPER[r["width"]]
        if r["min"] is None or r["max"] is None:
            lines.append(f"| {r['width']} × {2 * r['width']} | no feasible placement: {r['infeasible']} | | | | | |")
            continue
        gap = max(abs(r[k]["recheck"] - r[k]["energy"]) / r[k]["energy"] for k in ("min", "max"))
        lines.append(f"| {r['width']} × {2 * r['width']} | {r['min']['energy']:.2f} ({e_min:.2f}) | "
                     f"{r['max']['energy']:.2f} ({e_max:.2f}) | {r['gain'] * 100:.1f} ({gain:.2f}) | "
                     f"{location(r['min']['placement'])} | {location(r['max']['placement'])} | {gap * 100:.2f} % |")
    return lines


def observations(results: list[dict]) -> list[str]:
    """Facts computed from the results, for the discussion."""
    def pick(timing, regeneration):
        return [r for r in results if r["timing"] == timing and r["regeneration"] == regeneration and r["min"]]

    lines = []
    for timing, regeneration in CASES:
        rows = pick(timing, regeneration)
        if not rows:
            continue
        gains = [r["gain"] * 100 for r in sorted(rows, key=lambda r: r["width"])]
        min_xy = max(np.hypot(*r["min"]["placement"][:2]) for r in rows) * 1e3
        # How far the worst path's bounding box stays from the three cube faces that meet at Q-.
        max_to_faces = max(np.max(np.array(r["max"]["lowest_corner"]) - Q_MINUS_M) for r in rows) * 1e3
        phis = [abs(np.degrees(r["max"]["placement"][3])) for r in rows]
        ratio_min = np.mean([r["min"]["energy"] / PAPER[r["width"]][0] for r in rows])
        ratio_max = np.mean([r["max"]["energy"] / PAPER[r["width"]][1] for r in rows])
        falling = all(a >= b for a, b in zip(gains, gains[1:]))
        lines.append(f"- **{timing} timing, {regeneration}**: gain {gains[0]:.1f} % → {gains[-1]:.1f} % from 20 to 80 mm "
                     f"({'falling with size, as in the paper' if falling else 'not monotonic in size'}); minima within "
                     f"{min_xy:.0f} mm of O_b in (x, y); the worst paths come within {max_to_faces:.1f} mm of the three "
                     f"cube faces that meet at Q⁻, with |φ| between {min(phis):.0f}° and {max(phis):.0f}°; "
                     f"E_min / paper {ratio_min:.2f}, E_max / paper {ratio_max:.2f} on average.")
    bus, signed = pick("paper", "bus"), pick("paper", "signed")
    if bus and signed and all(abs(b["min"]["energy"] - s["min"]["energy"]) < 1e-9 * s["min"]["energy"]
                              for b, s in zip(sorted(bus, key=lambda r: r["width"]), sorted(signed, key=lambda r: r["width"]))):
        lines.append("- `bus` equals `signed` with the paper's timing law: the drives' summed power never turns "
                     "negative at these placements, so a shared bus already recovers every braking joule.")
    return lines


DISCUSSION = """\
## Why our numbers differ from the paper's, and where they agree

The paper prints no masses and no motor constants, so every energy above comes from the stated
estimates of `robots/orthoglide/` (6 kg platform, 2 kg sliders, 1 kg legs, R = 1.5 Ω,
K_t = 0.5 N·m/A, rotor and screw inertia reflected as 4.4 kg per slider); none was tuned to this
Table. Absolute energies therefore differ, and they differ in a telling way:

- With the paper's timing law (constant speed on each side, corners ignored), nothing accelerates
  except at the transitions the paper leaves out, so the energy is Joule loss from the 215 N radial
  cutting force and gravity plus the work of the cutting forces. Our E_min is then several times
  below the paper's, while E_max (braking counted as consumed or burnt) is of the same order: the
  paper's model spends energy that the stated timing law does not contain (its drives' constants, or
  motion it integrated that the text does not describe).
- The regeneration mode decides the answer, as expected: with full regeneration (`signed`) or a
  shared bus (`bus`) the energy depends less on where the path is, the gains are smaller and the
  least-energy placement leaves O_b for the faces of the cube; with per-axis clipping (`clip`, the
  default) or absolute power the landscape is the paper's.
- The realistic timing law (stop at each corner, jerk-limited feed with 10 m/s² and 500 m/s³) puts
  the energy of accelerating the 6 kg platform and the reflected rotor inertia back into the path;
  with it the magnitudes and the gains come closest to the Table.

What a faithful model must reproduce, and does in the `clip` and `absolute` modes: the minimum near
the isotropic point O_b with φ near 0° (or 90°: a rectangle's sides are then swapped between the
axes), the maximum at the edge of the cube nearest Q⁻ with φ near ±45°, energy insensitive to z,
and gains that fall as the rectangle grows. Every energy here is from the exact model (closed-loop
inverse dynamics of the full tree, legs included); each optimum was re-evaluated with a path sampled
four times more densely, and the largest relative change is in the last column.
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/paper_table.md", help="Markdown report to write")
    parser.add_argument("--time-step", type=float, default=0.002,
                        help="path sampling step of the reported energies (s); the global search uses at most 64")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="worker processes")
    parser.add_argument("--json", help="also write every case's numbers (energies, placements, re-checks) here")
    args = parser.parse_args()
    start = time.perf_counter()
    # Longest first, so that no worker is left with a long search at the end: the paper timing law's groups of
    # four modes (sharing the chain), the larger rectangles (more samples) first.
    groups = {timing: tuple(mode for t, mode in CASES if t == timing) for timing, _ in CASES}
    jobs = sorted(((w, timing, modes, args.time_step) for timing, modes in groups.items() for w in WIDTHS_MM),
                  key=lambda job: (-len(job[2]), -job[0]))
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        results = [case for group in pool.map(run_group, *zip(*jobs)) for case in group]
    elapsed = time.perf_counter() - start
    lines = ["# The paper's Table, reproduced", "",
             "Written by `python examples/paper_table.py` "
             f"({len(results)} searches of the least- and most-energy placement, {elapsed:.0f} s with {args.workers} "
             f"worker(s)). Orthoglide 3-axis, rectangles W × 2W milled at 0.66 m/s with F_f = 10 N, F_r = 215 N, "
             f"F_a = 25 N; x, y, z, φ free within the cube; energies from the path sampled every {args.time_step * 1e3:g} "
             "ms (the global search samples it at most 64 times). Paper values in parentheses.", ""]
    for timing, mode in CASES:
        lines += [f"## {timing.capitalize()} timing law, regeneration: {mode}", "", *table(results, timing, mode), ""]
    lines += ["## Observations (computed from the tables)", "", *observations(results), "", DISCUSSION]
    if args.json:
        Path(args.json).write_text(json.dumps({"seconds": elapsed, "workers": args.workers, "cases": results}))
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    kept = Path(args.out).read_text().split(CALIBRATION_MARKER, 1) if Path(args.out).is_file() else []
    calibration = CALIBRATION_MARKER + kept[1] if len(kept) == 2 else ""  # examples/paper_calibration.py's section
    Path(args.out).write_text("\n".join(lines) + "\n" + calibration)
    print(f"wrote {args.out} in {elapsed:.0f} s")


if __name__ == "__main__":
    main()
