"""Reports of placement results: readable text, JSON and per-sample CSV traces.

Text shows lengths in mm and angles in degrees; JSON and CSV files keep SI units (m, rad, J, ...)
and are written atomically (a reader never sees half a file).
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Collection
from pathlib import Path
from typing import Any

import numpy as np

from placement.contract.limit import Margin
from placement.contract.objective import OBJECTIVES, quantity, wording
from placement.energy.duty import SECONDS_PER_HOUR, DutyCycle, duty_cycle, rating_status
from placement.energy.integration import interval_widths
from placement.energy.trace import Drives
from placement.evaluation.evaluator import EvaluatorSettings
from placement.evaluation.results import PlacementDetail
from placement.files import staged
from placement.limits.collision import closest_points
from placement.path.toolpath import ToolPath
from placement.placing.profiles import (
    is_closed,
    knot_joint,
    knot_shares,
    length_variables,
    prismatic_joints,
    redundant_variables,
)
from placement.placing.transform import VARIABLES, describe_plane, transform_path_to_base
from placement.placing.values import angle_variable
from placement.robot.model import Robot
from placement.search.gap import OptimalityGap
from placement.search.optimize import Optimum, PlacementResult
from placement.search.space import REPORTED_DECIMALS
from placement.search.tolerance import ToleranceBox
from placement.search.uncertainty import Interval, Uncertainty
from placement.workshop.calibration import TOOL_FORCE_COLUMNS


def format_placement(placement: np.ndarray, names: tuple[str, ...] = VARIABLES, lengths: Collection[str] = ()) -> str:
    """'x = ... mm, ..., psi = ... deg' for a placement vector (m, rad) of variables ``names`` (a redundant robot's
    variables after the six in deg, but ``lengths`` in mm: a prismatic joint's knots), to REPORTED_DECIMALS (a
    search's optima lie on that grid: :func:`placement.search.reporting.as_printed`)."""
    return ", ".join(f"{name} = {np.degrees(value):.{REPORTED_DECIMALS}f} deg" if angle_variable(name, lengths)
                     else f"{name} = {value * 1e3:.{REPORTED_DECIMALS}f} mm" for name, value in zip(names, placement))


def _document_lengths(entry: dict[str, Any]) -> set[str]:
    """The knots of a placement's JSON entry that are lengths: those of the profiles given in m."""
    prismatic = {joint for joint, profile in entry.get("profiles", {}).items() if "position_m" in profile}
    return {name for name in entry["placement"] if knot_joint(name) in prismatic}


def results_lines(document: dict[str, Any]) -> list[str]:
    """The answer of one path's ``--json`` document as a few lines, for the scene page's results panel: each
    placement's objective and where it is (mm, deg), its tightest limit, and the gain."""
    lines = [str(document["path"])]
    for key, title in (("at", "--at"), ("best", "best"), ("worst", "worst")):
        entry = document.get(key)
        if entry is None:
            continue
        objective, value = entry["objective"], entry["objective"]["value"]
        shown = "none (unreachable)" if value is None else quantity(value, objective["unit"])
        lines.append(f"{title}: {objective['title']} {shown}")
        lines.append("  " + format_placement(np.array(list(entry["placement"].values())), tuple(entry["placement"]),
                                             _document_lengths(entry)))
        if entry["margins"]:
            tight = min(entry["margins"], key=lambda margin: margin["margin"])
            lines.append(f"  tightest: {tight['kind']} ({tight['where']}), margin {tight['margin'] * 100:.1f} %")
    if document.get("gain") is not None:
        lines.append(f"gain: {document['gain'] * 100:.1f} % of the {document['objective'].replace('_', ' ')}")
    return lines


def placement_duty(robot: Robot, detail: PlacementDetail, rest_s: float = 0.0) -> DutyCycle | None:
    """The placement's duty cycle with ``rest_s`` (s) between passes (:mod:`placement.energy.duty`), or None when no
    drive gives a continuous torque or the placement has no timing."""
    drives = Drives.of(robot)
    if not detail.reachable or not np.isfinite(detail.duration_s) or not np.isfinite(drives.continuous_torque_Nm).any():
        return None
    return duty_cycle(drives, detail.motor.torque_Nm, interval_widths(detail.samples.t_s, detail.samples.piece),
                      detail.hold_effort, rest_s)


def format_duty(robot: Robot, duty: DutyCycle) -> list[str]:
    """Text lines of a duty cycle: each rated motor's RMS torque against its rating (its source's status where the
    sidecar gives one), and the cycles per hour."""
    statuses = rating_status(robot)
    width = max(14, max(len(a.joint) for a in robot.actuators) + 2)
    rest = f" + a rest of {duty.rest_s:g} s holding the end pose" if duty.rest_s else " back to back"
    lines = [f"  duty cycle (RMS motor torque over a pass of {duty.cycle_s:.4f} s{rest}, against the rated "
             "continuous torque):"]
    for i, actuator in enumerate(robot.actuators):
        if np.isfinite(duty.continuous_torque_Nm[i]):
            lines.append(f"    {actuator.joint:<{width}s}RMS {duty.rms_torque_Nm[i]:.4g} N m = {duty.ratio[i] * 100:.1f} % "
                         f"of {duty.continuous_torque_Nm[i]:.4g} N m{f' {statuses[i]}' if statuses[i] else ''} "
                         f"(hold {duty.hold_torque_Nm[i]:.4g} N m)")
    if duty.cycles_per_hour == 0:
        lines.append("  cycles per hour: none (a motor's hold torque alone exceeds its rating)")
    elif duty.limited_by is None:
        lines.append(f"  at most {duty.cycles_per_hour:.0f} cycles per hour (set by the pass and the rest; every motor "
                     "stays within its rating)")
    else:
        needed = SECONDS_PER_HOUR / duty.cycles_per_hour - duty.cycle_s
        lines.append(f"  at most {duty.cycles_per_hour:.0f} cycles per hour ({robot.actuators[duty.limited_by].joint} "
                     f"needs a rest of {needed:.4g} s after each pass to stay within its rating)")
    return lines


def duty_json(robot: Robot, duty: DutyCycle) -> dict[str, Any]:
    """JSON-ready duty cycle (SI): per actuator RMS torque, rating, ratio and hold torque; cycles per hour."""
    names = [a.joint for a in robot.actuators]

    def per_actuator(values: np.ndarray) -> dict[str, float | None]:
        return {name: float(value) if np.isfinite(rated) else None
                for name, value, rated in zip(names, values, duty.continuous_torque_Nm, strict=True)}

    return {"cycle_s": duty.cycle_s, "rest_s": duty.rest_s, "rms_torque_Nm": dict(zip(names, map(float, duty.rms_torque_Nm))),
            "continuous_torque_Nm": per_actuator(duty.continuous_torque_Nm), "ratio": per_actuator(duty.ratio),
            "rating_source": dict(zip(names, rating_status(robot))),
            "hold_torque_Nm": dict(zip(names, map(float, duty.hold_torque_Nm))),
            "cycles_per_hour": duty.cycles_per_hour,
            "limited_by": None if duty.limited_by is None else names[duty.limited_by]}


def format_detail(title: str, robot: Robot, detail: PlacementDetail, recheck_value: float | None = None,
                  rest_s: float = 0.0) -> str:
    """Text block for one placement: where, objective, energy per actuator and its parts, duty cycle (with ``rest_s``
    s between passes, where the drives give a continuous torque), tightest limits."""
    names = VARIABLES + redundant_variables(robot)
    lines = [title, f"  {format_placement(detail.placement, names, length_variables(robot))}"]
    lines += [f"  {line}" for line in profile_lines(robot, detail)]
    if not detail.reachable:
        first = detail.unreachable_samples[0]
        lines.append(f"  unreachable: {len(detail.unreachable_samples)} of {len(detail.samples)} samples have no "
                     f"configuration (first at t = {detail.samples.t_s[first]:.4f} s)")
        return "\n".join(lines)
    energy = detail.energy
    if not np.isfinite(energy.total_J):
        lines.append("  energy not finite: the numbers overflow (check the path's size, feed and forces, and the robot's "
                     "masses)")
        return "\n".join(lines)
    words = wording(detail.objective)
    lines.append(_value_line(words.subject, detail.value, words.unit, recheck_value))
    if detail.objective != "energy":
        lines.append(f"  energy {energy.total_J:.4f} J")
    if detail.timing == "optimal" and detail.objective != "cycle_time":
        lines.append(f"  cycle time {detail.duration_s:.4f} s (optimal timing)" if np.isfinite(detail.duration_s)
                     else "  cycle time: no timing keeps every limit (optimal timing)")
    if detail.deflection is not None:
        lines.append(_deflection_line(detail))
    width = max(14, max(len(a.joint) for a in robot.actuators) + 2)
    if not detail.feasible:
        lines[-1] += ("  INFEASIBLE: a limit is exceeded" if not detail.required_margin else
                      f"  INFEASIBLE: a limit is closer than the {detail.required_margin * 100:g} % margin")
    lines += [f"    {'actuator':<{width}s}{'energy J':>10s}{'Joule J':>10s}{'induct. J':>11s}{'back-EMF J':>12s}"
              f"{'shaft J':>10s}"]
    for i, actuator in enumerate(robot.actuators):
        lines.append(f"    {actuator.joint:<{width}s}{energy.per_actuator_J[i]:>10.4f}{energy.joule_J[i]:>10.4f}"
                     f"{energy.inductive_J[i]:>11.4f}{energy.back_emf_J[i]:>12.4f}{energy.mechanical_J[i]:>10.4f}")
    duty = placement_duty(robot, detail, rest_s)
    if duty is not None:
        lines += format_duty(robot, duty)
    lines.append("  tightest limits (margin: share of the range, speed or torque still free; for a collision, "
                 "clearance beyond the required one, per 100 mm):")
    # Reachability is said above when it fails; a timing that exists needs no line.
    shown = [m for m in detail.margins if m.kind != "reachability" and not (m.kind == "optimal timing" and m.margin >= 0)]
    where = max(10, max(len(m.where) for m in shown))
    for margin in sorted(shown, key=lambda m: m.margin):
        lines.append(f"    {margin.kind:<18s} {margin.where:<{where}s} margin {margin.margin * 100:6.1f} %  "
                     f"({margin.value:.4g} {margin.unit} against {margin.limit:.4g} {margin.unit}, "
                     f"t = {detail.samples.t_s[margin.sample]:.4f} s{_closest_text(robot, detail, margin)})")
    return "\n".join(lines)


def _deflection_line(detail: PlacementDetail) -> str:
    """The tool's deflection under the process forces: largest (where, which way) and RMS."""
    bend = detail.deflection
    assert bend is not None
    if bend.largest_m == 0.0:  # no process force on the path (a weld seam, a pen): no direction to name
        return "  tool deflection: none (the path has no process force)"
    rotation = "" if bend.largest_rotation_rad is None else f", rotation up to {bend.largest_rotation_rad * 1e6:.4g} µrad"
    loaded = "" if bend.loaded_correction is None else (
        f"; at the loaded equilibrium, which changes it by at most {bend.loaded_correction:.2g} of the largest linear one")
    return (f"  tool deflection under the process forces: largest {bend.largest_m * 1e6:.4g} µm at "
            f"{bend.arc_length_m * 1e3:.1f} mm along the path (t = {detail.samples.t_s[bend.sample]:.4f} s) along "
            f"({', '.join(f'{c:.3f}' for c in bend.direction)}) in the base frame, RMS {bend.rms_m * 1e6:.4g} µm"
            f"{rotation}{loaded}")


def _deflection_json(detail: PlacementDetail) -> dict[str, Any] | None:
    """The tool's deflection under the process forces (µm; where along the path, the base frame's direction; with the
    loaded correction, the largest change it makes relative to the largest linear deflection)."""
    bend = detail.deflection
    if bend is None:
        return None
    out = {"largest_um": bend.largest_m * 1e6, "rms_um": bend.rms_m * 1e6,
           "where": {"sample": bend.sample, "arc_length_m": bend.arc_length_m,
                     "t_s": float(detail.samples.t_s[bend.sample])},
           "direction": bend.direction.tolist(), "largest_rotation_rad": bend.largest_rotation_rad}
    if bend.loaded_correction is not None:
        out["loaded_correction"] = bend.loaded_correction
    return out


def _closest_text(robot: Robot, detail: PlacementDetail, margin: Margin) -> str:
    """Where a collision margin's two bodies come nearest, in mm of the base frame ("" for other limits)."""
    if margin.kind != "collision":
        return ""
    first, second = closest_points(robot, detail.configuration[margin.sample], margin.where)
    return ", nearest at ({:.1f}, {:.1f}, {:.1f}) mm".format(*((first + second) / 2 * 1e3))


def _value_line(title: str, value: float, unit: str, recheck: float | None) -> str:
    text = f"  {title} {quantity(value, unit)}"
    if recheck is not None:
        change = f"{(recheck - value) / value * 100:+.3f} %" if value else "n/a"
        text += f" (4x denser sampling: {quantity(recheck, unit)}, {change})"
    return text


def _recheck_line(optimum: Optimum) -> str:
    """Whether every limit still holds on the 4x denser sampling, and the tightest one there."""
    margin = f"{optimum.recheck_limit}, margin {optimum.recheck_margin * 100:.4f} %"
    required = optimum.detail.required_margin
    kept = f" with the {required * 100:g} % margin" if required else ""
    note = f"\n  note: {optimum.note}" if optimum.note else ""
    if optimum.guide_value is not None and optimum.guide_gap is not None:
        unit = OBJECTIVES.get(optimum.detail.objective).unit
        note += (f"\n  search guided by a cheaper model of the long path (its lines and flat arcs merged into chords, "
                 f"or sampled more coarsely): {quantity(optimum.guide_value, unit)} here against the exact "
                 f"{quantity(optimum.detail.value, unit)} (gap {optimum.guide_gap * 100:+.3f} %)")
    if optimum.holds:
        return f"  4x denser sampling: every limit holds{kept} (tightest: {margin}){note}"
    if optimum.recheck_limit.startswith("reachability"):
        return f"  4x denser sampling: the path leaves the robot's reach between its samples{note}"
    return (f"  4x denser sampling: a limit is exceeded{kept} between the path's samples ({margin}); "
            f"sample the path more finely (--time-step) if that matters{note}")


def format_basins(optimum: Optimum, names: tuple[str, ...] = VARIABLES, lengths: Collection[str] = ()) -> str:
    """Lines: the other basins (distinct local optima) within the search's share of this optimum, as printed, and which
    of them are within the 4x denser re-check's resolution of it; or that the search found none (``lengths``: as for
    :func:`format_placement`)."""
    words = wording(optimum.detail.objective)
    share = f"{optimum.basin_share * 100:g} %"
    if not optimum.basins:
        return f"  other basins: none found within {share} of this {words.subject}"
    close = optimum.unresolved
    lines = [f"  other basins within {share} (distinct local optima, as printed):"]
    for basin in optimum.basins:
        change = (basin.value - optimum.detail.value) / (abs(optimum.detail.value) or 1.0)
        fails = "" if basin.holds else ", fails a limit once printed or on the 4x denser re-check"
        tie = ", within the 4x re-check's resolution of this one" if any(basin is c for c in close) else ""
        lines.append(f"    {quantity(basin.value, words.unit)} ({change * 100:+.3f} %{fails}{tie}) at "
                     f"{format_placement(basin.placement, names, lengths)}")
    if close:
        lines.append("    the path's sampling, not the placement, may decide between them: sample the path more finely "
                     "(--time-step) to rank them")
    return "\n".join(lines)


def basins_json(optimum: Optimum, names: tuple[str, ...] = VARIABLES) -> list[dict[str, Any]]:
    """JSON-ready list of the other basins near an optimum (SI units): placement, objective value (and energy_J for
    the energy) on the path's sampling and the 4x denser one, whether it holds, and whether it is within the
    re-check's resolution of the optimum."""
    close = optimum.unresolved
    return [{"placement": {name: float(v) for name, v in zip(names, basin.placement, strict=True)},
             "value": _finite(basin.value), "recheck_value": _finite(basin.recheck_value),
             **({"energy_J": _finite(basin.value)} if optimum.detail.objective == "energy" else {}),
             "relative_difference": _finite((basin.value - optimum.detail.value) / (abs(optimum.detail.value) or 1.0)),
             "holds": basin.holds, "within_recheck_resolution": any(basin is c for c in close)}
            for basin in optimum.basins]


def format_uncertainty(uncertainty: Uncertainty) -> str:
    """The error bars, once and compactly: what was varied, each quantity's first-order interval and sampled range,
    and how often another basin wins (:mod:`placement.search.uncertainty`)."""
    statuses: dict[str, int] = {}
    for parameter in uncertainty.parameters:
        statuses[parameter.status] = statuses.get(parameter.status, 0) + 1
    varied = ", ".join(f"{count} {status}" for status, count in statuses.items())

    def shown(name: str, interval: Interval | None, unit: str, factor: float = 1.0, digits: int = 4) -> str | None:
        if interval is None:
            return None
        v, lo, hi, slo, shi = (factor * x for x in (interval.value, interval.low, interval.high, interval.sampled_low,
                                                    interval.sampled_high))
        return f"{name} {v:.{digits}f} [{lo:.{digits}f}, {hi:.{digits}f}]{unit} (sampled {slo:.{digits}f} to {shi:.{digits}f})"

    parts = [text for text in (shown("best", uncertainty.best, " J"), shown("worst", uncertainty.worst, " J"),
                               shown("gain", uncertainty.gain, " %", 100.0, 1)) if text]
    return (f"error bars ({len(uncertainty.parameters)} drive constants varied: {varied}; {uncertainty.method}, "
            f"{uncertainty.samples} draws): " + "; ".join(parts)
            + f"; another basin takes less energy than the best in {uncertainty.other_basin_wins * 100:.0f} % of draws")


def uncertainty_json(uncertainty: Uncertainty) -> dict[str, Any]:
    """JSON-ready error bars (SI; the gain a share): the parameters with ranges and status, each quantity's value,
    first-order interval and sampled range, and the share of draws in which another basin wins."""
    def interval(value: Interval | None) -> dict[str, float] | None:
        return None if value is None else {"value": value.value, "low": value.low, "high": value.high,
                                           "sampled_low": value.sampled_low, "sampled_high": value.sampled_high}

    return {"method": uncertainty.method, "samples": uncertainty.samples,
            "parameters": [{"key": p.key, "status": p.status, "value": p.value, "low": p.low, "high": p.high}
                           for p in uncertainty.parameters],
            "best_energy_J": interval(uncertainty.best), "worst_energy_J": interval(uncertainty.worst),
            "gain": interval(uncertainty.gain), "other_basin_wins": uncertainty.other_basin_wins}


def format_gap(gap: OptimalityGap, unit: str) -> str:
    """One line: the best found, the lower bound, the gap and its kind, and what the bound cost
    (:mod:`placement.search.gap`)."""
    reach = (f"; {gap.out_of_reach_share:.1%} of the box dropped as small cells out of reach"
             if gap.out_of_reach_share else "")
    return (f"optimality gap ({gap.kind}, not a proof: derivative bounds sampled, times {gap.safety:g}): best found "
            f"{gap.best:.4f}{unit} − lower bound {gap.lower_bound:.4f}{unit} = {gap.gap:.4f}{unit} "
            f"({gap.relative:.2%}); {gap.evaluations} evaluations, {gap.seconds:.1f} s, {gap.cells} cells left open"
            + reach)


def gap_json(gap: OptimalityGap) -> dict[str, Any]:
    """JSON-ready optimality gap (objective units; the slope bounds per m or rad of each free variable)."""
    return {"kind": gap.kind, "best": gap.best, "lower_bound": gap.lower_bound, "gap": gap.gap,
            "relative": gap.relative, "evaluations": gap.evaluations, "safety_factor": gap.safety,
            "lipschitz": gap.lipschitz.tolist(), "open_cells": gap.cells,
            "out_of_reach_share": gap.out_of_reach_share, "seconds": gap.seconds}


def format_tolerance(box: ToleranceBox, subject: str, lengths: Collection[str] = ()) -> str:
    """One line: the tolerance box's half-widths (mm, degrees; ``lengths``: as for :func:`format_placement`) and how it
    was checked."""
    widths = ", ".join(f"{name} ± {np.degrees(width):.2f} deg" if angle_variable(name, lengths)
                       else f"{name} ± {width * 1e3:.2f} mm" for name, width in zip(box.free, box.half_width, strict=True))
    return (f"  tolerance (every limit holds and the {subject} stays within {box.within * 100:g} % of this placement's "
            f"throughout the box): {widths} (checked at {box.corners_checked} corners and {box.inside_checked} points "
            f"inside, "
            f"{box.evaluations} evaluations{' on the guide model of the search' if box.guided else ''})"
            + ("; ± 0: a limit is already tight at this placement along that variable" if not box.half_width.all() else ""))


def tolerance_json(box: ToleranceBox) -> dict[str, Any]:
    """JSON-ready tolerance box (SI): half-widths per free variable (m, rad)."""
    return {"within": box.within, "half_width": {name: float(w) for name, w in zip(box.free, box.half_width, strict=True)},
            "evaluations": box.evaluations, "corners_checked": box.corners_checked,
            "inside_checked": box.inside_checked, **({"guided": True} if box.guided else {})}


def format_result(robot: Robot, result: PlacementResult, rest_s: float = 0.0,
                  boxes: dict[str, ToleranceBox] | None = None) -> str:
    """Text report of a search: best and worst placements, their tolerance boxes where given ({"best"|"worst": box}),
    and the gain (``rest_s``: rest between passes, s)."""
    words = wording(result.objective)
    blocks = []
    for key, title, optimum in (("best", f"best placement ({words.best} {words.subject})", result.best),
                                ("worst", f"worst placement ({words.worst} {words.subject})", result.worst)):
        if optimum is not None:
            box, lengths = (boxes or {}).get(key), length_variables(robot)
            blocks.append(format_detail(title, robot, optimum.detail, optimum.recheck_value, rest_s) + "\n"
                          + _recheck_line(optimum) + "\n"
                          + format_basins(optimum, VARIABLES + redundant_variables(robot), lengths)
                          + ("" if box is None else "\n" + format_tolerance(box, words.subject, lengths)))
    if result.best is not None and result.worst is not None and not (result.best.holds and result.worst.holds):
        blocks.append(f"gain: not given, the {'best' if not result.best.holds else 'worst'} placement fails its "
                      "4x denser re-check")
    if result.gain is not None and result.best is not None and result.worst is not None:
        difference = abs(result.worst.detail.value - result.best.detail.value)
        per_pass = " per pass" if words.unit == "J" else ""
        blocks.append(f"gain: placing the path at the best instead of the worst placement {words.gain_verb} "
                      f"{result.gain * 100:.1f} % of the {words.subject} ({quantity(difference, words.unit)}{per_pass})")
    return "\n\n".join(blocks)


def job_document(robot: Robot, path: ToolPath, evaluation: EvaluatorSettings, samples: int) -> dict[str, Any]:
    """The head of the main job's JSON document for one path: robot, path, objective, regeneration policy, timing
    law, number of samples, margin kept (a share), for a planar robot its plane, for a workpiece on a positioner the
    frame the placement is in (``workpiece_frame``), and the moving links without
    inertia it was loaded with (``massless_links``, with ``--allow-massless``), whose inertia the energies leave out."""
    document: dict[str, Any] = {"robot": robot.name, "path": path.name, "objective": evaluation.objective,
                                "regeneration": evaluation.regeneration, "timing": path.timing.mode,
                                "samples": samples, "margin": evaluation.margin}
    if robot.plane is not None:
        document["plane"] = describe_plane(robot.plane)
    if robot.workpiece_frame is not None:  # the placement is in this frame, which the profiled joints move
        document["workpiece_frame"] = robot.workpiece_frame
    if robot.massless_links:  # loaded as asked (--allow-massless): the energies leave out their inertia
        document["massless_links"] = list(robot.massless_links)
    return document


def detail_json(robot: Robot, detail: PlacementDetail, optimum: Optimum | None = None,
                rest_s: float = 0.0) -> dict[str, Any]:
    """JSON-ready dictionary of one placement (SI units); ``duty`` where the drives give a continuous torque."""
    names = [a.joint for a in robot.actuators]
    objective = OBJECTIVES.get(detail.objective)
    out: dict[str, Any] = {
        "placement": {name: float(value) for name, value in
                      zip(VARIABLES + redundant_variables(robot), detail.placement, strict=True)},
        "objective": {"name": detail.objective, "title": objective.title, "unit": objective.unit,
                      "value": float(detail.value) if detail.reachable else None},
        "feasible": detail.feasible,
        "margin_kept": detail.required_margin,
        "reachable": detail.reachable,
        "energy_J": float(detail.energy.total_J) if detail.reachable else None,
        "energy_per_actuator_J": dict(zip(names, map(float, detail.energy.per_actuator_J))) if detail.reachable else None,
        "energy_parts_J": {part: dict(zip(names, map(float, getattr(detail.energy, f"{part}_J"))))
                           for part in ("joule", "inductive", "back_emf", "mechanical")} if detail.reachable else None,
        "cycle_time_s": detail.duration_s if detail.reachable and np.isfinite(detail.duration_s) else None,
        "margins": [_margin_json(robot, detail, m) for m in detail.margins] if detail.reachable else [],
    }
    deflection = _deflection_json(detail)
    if deflection is not None:
        out["deflection"] = deflection
    if robot.redundant_joints:
        out["profiles"] = profiles_json(robot, detail)
    duty = placement_duty(robot, detail, rest_s)
    if duty is not None:
        out["duty"] = duty_json(robot, duty)
    if optimum is not None:
        recheck = _finite(optimum.recheck_value)
        out["objective"]["recheck_value"] = recheck
        if recheck is None:
            out["objective"]["recheck_null_reason"] = (
                "the path leaves the robot's reach between its samples"
                if optimum.recheck_limit.startswith("reachability") else "not finite on the 4x denser sampling")
        out["recheck_tightest"] = {"limit": optimum.recheck_limit, "margin": optimum.recheck_margin}
        out["recheck_holds"] = optimum.holds
        if detail.objective == "energy":
            out["recheck_energy_J"] = recheck
        out["evaluations"] = optimum.evaluations
        out["note"] = optimum.note
        out["basins"] = basins_json(optimum, VARIABLES + redundant_variables(robot))
        out["basin_share"] = optimum.basin_share
        if optimum.guide_value is not None:
            out["guide"] = {"value": _finite(optimum.guide_value), "gap": _finite(optimum.guide_gap or 0.0)}
    return out


def profiles_json(robot: Robot, detail: PlacementDetail) -> dict[str, Any]:
    """Each redundant joint's profile along the path (rad, or m for a prismatic joint: ``knots_m``, ``position_m``): its
    knots and the share of arc length each stands at, and its value at every sample (``t_s``), as the exact chain
    moved it."""
    knots = robot.profile_knots
    shares = knot_shares(knots, is_closed(detail.samples))
    start = 6 + robot.tool_spin
    given = detail.placement[start:].reshape(-1, knots) if len(detail.placement) > start else None
    out: dict[str, Any] = {}
    prismatic = prismatic_joints(robot)
    for r, (joint, q) in enumerate(zip(robot.redundant_joints, robot.redundant_q_indices, strict=True)):
        unit = "m" if joint in prismatic else "rad"
        out[joint] = {f"knots_{unit}": None if given is None else given[r].tolist(), "knot_shares": shares.tolist(),
                      "t_s": detail.samples.t_s.tolist(), f"position_{unit}": detail.configuration[:, q].tolist()}
    return out


def profile_lines(robot: Robot, detail: PlacementDetail) -> list[str]:
    """A line per redundant joint: its range along the path and its knots (deg, or mm for a prismatic joint)."""
    lines, prismatic = [], prismatic_joints(robot)
    for joint, q in zip(robot.redundant_joints, robot.redundant_q_indices, strict=True):
        scale, unit = (1e3, "mm") if joint in prismatic else (180 / np.pi, "deg")
        values = detail.configuration[:, q] * scale
        lines.append(f"{joint} along the path: {values[0]:.2f} {unit} at the start, {values.min():.2f} to "
                     f"{values.max():.2f} {unit}, {values[-1]:.2f} {unit} at the end ({robot.profile_knots} knot(s) over "
                     "the arc length)")
    return lines


def _margin_json(robot: Robot, detail: PlacementDetail, margin: Margin) -> dict[str, Any]:
    """One tightest limit; a collision's also with the two bodies' nearest points (base frame, m)."""
    out = {"kind": margin.kind, "where": margin.where, "margin": margin.margin, "value": margin.value,
           "limit": margin.limit, "unit": margin.unit, "t_s": float(detail.samples.t_s[margin.sample])}
    if margin.kind == "collision":
        out["nearest_points_m"] = [p.tolist() for p in closest_points(robot, detail.configuration[margin.sample],
                                                                       margin.where)]
    return out


def write_atomically(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file in the same folder and a rename (:func:`staged`)."""
    with staged(path, text):
        pass


def _finite(value: float) -> float | None:
    """``value`` as a float, or None where it is infinite or NaN (which strict JSON has no word for)."""
    return float(value) if np.isfinite(value) else None


def strict(document: Any) -> Any:
    """``document`` with every infinite or NaN number (numpy's too) replaced by None, as strict JSON needs."""
    if isinstance(document, dict):
        return {key: strict(value) for key, value in document.items()}
    if isinstance(document, list | tuple):
        return [strict(value) for value in document]
    if isinstance(document, float | np.floating):
        return _finite(float(document))
    return document


def json_text(document: dict[str, Any]) -> str:
    """A JSON document as ``--json`` writes it: indented, strict (an infinite or NaN number is null, :func:`strict`)."""
    return json.dumps(strict(document), indent=2, allow_nan=False) + "\n"


def write_json(path: str | Path, document: dict[str, Any]) -> None:
    """Write a JSON document atomically, as :func:`json_text` gives it."""
    write_atomically(path, json_text(document))


def write_trace(path: str | Path, robot: Robot, detail: PlacementDetail) -> None:
    """Write the per-sample CSV trace of one placement (SI units), atomically.

    Columns: t, x, y, z (tool point in the base frame), speed (the tool's speed along the path, m/s),
    tool_force_x, tool_force_y, tool_force_z (the process force on the tool from the workpiece, base
    frame, N), then for each actuator, named by its joint: q_JOINT, qd_JOINT, qdd_JOINT, force_JOINT
    (N or N·m at the joint), motor_speed_JOINT (rad/s), motor_torque_JOINT (N·m), current_JOINT (A),
    power_JOINT (W, electric); where the robot gives its stiffness, deflection_x, deflection_y, deflection_z (the
    tool point's deflection under the process force, base frame, m). The names are a calibration log's
    (:func:`placement.workshop.calibration.read_log`): the trace calibrates the drives it was made with,
    its rates and process force included. Two rows of one time are the motion either side of a step
    in its acceleration (a segment's end, a switch of the optimal timing law).
    """
    names = [actuator.joint for actuator in robot.actuators]
    quantities = ("q", "qd", "qdd", "force", "motor_speed", "motor_torque", "current", "power")
    columns = ["t", "x", "y", "z", "speed", *TOOL_FORCE_COLUMNS] + [f"{quantity}_{name}" for name in names
                                                                   for quantity in quantities]
    per_actuator = [detail.position, detail.velocity, detail.acceleration, detail.effort, detail.motor.speed_rad_s,
                    detail.motor.torque_Nm, detail.motor.current_A, detail.power_W]
    speed = np.linalg.norm(detail.samples.velocity_m_s, axis=1)
    force = transform_path_to_base(detail.samples, detail.placement, robot.plane)[1]
    table = np.column_stack([detail.samples.t_s, detail.tool_position_m, speed, force]
                            + [values[:, i] for i in range(len(names)) for values in per_actuator])
    if detail.deflection is not None:
        columns += ["deflection_x", "deflection_y", "deflection_z"]
        table = np.column_stack([table, detail.deflection.translation_m])
    buffer = io.StringIO()
    writer = csv.writer(buffer)
    writer.writerow(columns)
    writer.writerows(np.vectorize(lambda v: f"{v:.9g}")(table).tolist())
    write_atomically(path, buffer.getvalue())
