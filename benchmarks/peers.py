"""Our search against plain peer optimisers at the same wall time, on the same exact model.

Run: ``python benchmarks/peers.py [--problems groove ur5 pocket] [--seeds 0 1 ... 9] [--peers de de5 tpe cmaes ipop]``
(Optuna comes with the ``bench`` extra: ``pip install -e .[bench]``). The problems: the paper's groove
(Orthoglide, examples/rect.yaml), the UR5 on the same rectangle, and the G-code pocket in the Orthoglide's cell
(examples/pocket.yaml, examples/cell_orthoglide.yaml), as the README runs them. The table goes to the console and
to the script's section of benchmarks/RESULTS.md (:mod:`results`, with the date, the machine, its load and the
command).

For each problem and seed, our search (least energy only, its default budget) runs first and the CPU time it
took is the budget of each peer: scipy's ``differential_evolution`` as a user calls it (``de``: its default
population, 15 per variable) and with a small population that runs more generations in the same time (``de5``: 5
per variable), and Optuna's TPE and CMA-ES samplers (``cmaes``; ``ipop``: CMA-ES restarting with a growing
population). Every search runs in this one process on one core (least energy only: ours starts no process), and
the budget is the process's CPU time, not wall time: on a machine shared with other jobs, wall time depends on
their load from moment to moment, and would give the later searches of a row less or more than ours had.
Every peer evaluates the same exact model as our polish and our reported values (the Evaluator at
the path's own sampling), over the same box, and counts a placement feasible as our search does
(every margin ≥ 0); each prints its best feasible energy. The script also times our chain (batched
kinematics and RNEA) against a plain Pinocchio loop over the samples (Newton inverse kinematics
and ``pinocchio.rnea`` per sample) on the UR5, in the same run, and prints the ratio.
"""

from __future__ import annotations

import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_variable] = "1"  # one core, before numpy loads

import argparse  # noqa: E402
import itertools  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy.optimize import NonlinearConstraint, differential_evolution  # noqa: E402

from placement import equip, load_cell, load_robot  # noqa: E402
from placement.cli.memory import keep_freed_memory  # noqa: E402
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings  # noqa: E402
from placement.path.load import load_path  # noqa: E402
from placement.search.optimize import SearchSettings, optimize_placement  # noqa: E402
from placement.search.space import default_space, printed, printed_steps  # noqa: E402

ROOT = Path(__file__).parents[1]
PROBLEMS = {"groove": ("orthoglide", "examples/rect.yaml", None),  # robot, path, cell (from the repository's root)
            "ur5": ("ur5", "examples/rect.yaml", None),
            "pocket": ("orthoglide", "examples/pocket.yaml", "examples/cell_orthoglide.yaml")}
PEERS = ("de", "de5", "tpe", "cmaes", "ipop")
DE_POPULATIONS = {"de": 15, "de5": 5}  # differential evolution's population per variable (scipy's default: 15)


class Budgeted:
    """The exact model at the path's own sampling, counting the best feasible energy and the time spent."""

    def __init__(self, evaluator: Evaluator, space, seconds: float) -> None:
        self.evaluator, self.space, self.seconds = evaluator, space, seconds
        self.best, self.best_x = np.inf, np.full(len(space.free), np.nan)
        self.start = time.process_time()

    @property
    def over(self) -> bool:
        return time.process_time() - self.start >= self.seconds

    def __call__(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        evaluation = self.evaluator.evaluate(self.space.full(np.atleast_2d(points)))
        values, margins = np.asarray(evaluation.value, float), np.asarray(evaluation.margins, float)
        feasible = (margins >= 0).all(axis=1) & np.isfinite(values)
        if feasible.any() and values[feasible].min() < self.best:
            k = int(np.argmin(np.where(feasible, values, np.inf)))
            self.best, self.best_x = float(values[k]), np.atleast_2d(points)[k].copy()
        return values, margins


def run_de(evaluator: Evaluator, space, seconds: float, seed: int, popsize: int = 15) -> Budgeted:
    budget = Budgeted(evaluator, space, seconds)
    n_limits = budget(space.lower)[1].shape[1]
    cache: dict[bytes, tuple[float, np.ndarray]] = {}

    def lookup(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        points = np.atleast_2d(points)
        todo = [p for p in points if p.tobytes() not in cache]
        if todo:
            values, margins = budget(np.array(todo))
            for p, v, m in zip(todo, values, margins, strict=True):
                cache[p.tobytes()] = (float(v), m)
        got = [cache[p.tobytes()] for p in points]
        return np.array([g[0] for g in got]), np.array([g[1] for g in got])

    def objective(points: np.ndarray) -> np.ndarray:
        values = lookup(np.asarray(points).T)[0]
        return np.where(np.isfinite(values), values, 1e30)

    def margins(points: np.ndarray) -> np.ndarray:
        m = lookup(np.asarray(points).T)[1]
        return m.T if np.ndim(points) > 1 else m[0]

    differential_evolution(objective, list(zip(space.lower, space.upper)), vectorized=True, updating="deferred",
                           constraints=NonlinearConstraint(margins, np.zeros(n_limits), np.inf),
                           popsize=popsize, maxiter=100_000, tol=0.0, polish=False, rng=np.random.default_rng(seed),
                           callback=lambda intermediate_result: budget.over)
    return budget


def run_optuna(evaluator: Evaluator, space, seconds: float, seed: int, kind: str) -> Budgeted:
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    warnings.filterwarnings("ignore", category=FutureWarning)  # constraints_func, Optuna 5's deprecation
    budget = Budgeted(evaluator, space, seconds)
    if kind == "tpe":
        sampler: optuna.samplers.BaseSampler = optuna.samplers.TPESampler(
            seed=seed, constraints_func=lambda trial: trial.user_attrs["violation"])
    else:
        sampler = optuna.samplers.CmaEsSampler(seed=seed, restart_strategy="ipop" if kind == "ipop" else None)
    study = optuna.create_study(sampler=sampler)
    batch = 16
    while not budget.over:
        trials = [study.ask() for _ in range(batch)]
        points = np.array([[t.suggest_float(name, lo, hi) for name, lo, hi in zip(space.free, space.lower, space.upper)]
                           for t in trials])
        values, margins = budget(points)
        for trial, value, margin in zip(trials, values, margins, strict=True):
            violation = np.clip(-margin, 0.0, None)
            trial.set_user_attr("violation", [float(violation.sum())])
            penalised = value if violation.sum() == 0 and np.isfinite(value) else 1e3 + 1e3 * float(violation.sum())
            study.tell(trial, float(min(penalised, 1e30)))
    return budget


def as_printed(evaluator: Evaluator, space, x: np.ndarray) -> float:
    """The least energy of the corners of the printed grid's cell around the free values ``x`` (as our report prints a
    placement, 0.01 mm and 0.01°) that lie in the box and keep every limit: a peer's best as a user would enter it
    (our report re-checks its corners on a 4x denser sampling too, which can only leave it fewer)."""
    if not np.isfinite(x).all():
        return np.inf
    angles = space.angles[space.indices]
    steps = printed_steps(angles)
    low = np.floor(x / steps) * steps
    corners = np.array([[printed(value, angle) for value, angle in zip(low + steps * np.array(bits), angles)]
                        for bits in itertools.product((0, 1), repeat=len(x))])
    inside = ((corners >= space.lower - 1e-12) & (corners <= space.upper + 1e-12)).all(axis=1)
    evaluation = evaluator.evaluate(space.full(corners))
    usable = inside & (evaluation.margins >= 0).all(axis=1) & np.isfinite(evaluation.value)
    return float(evaluation.value[usable].min()) if usable.any() else np.inf


def chain_against_loop(seconds: float) -> tuple[float, float, float]:
    """Samples/s of our chain (kinematics and RNEA, batched) and of a plain Pinocchio loop, UR5, one core."""
    import pinocchio as pin

    from placement.dynamics.inverse import inverse_dynamics
    from placement.kinematics.trajectories import TaskTrajectory

    robot = load_robot("ur5")
    model, data = robot.model, robot.model.createData()
    frame = robot.end_effector_frame_id
    samples = 500
    w = 0.66 / 0.05
    t = np.linspace(0.0, 2 * np.pi / w, samples)[:, None]
    q0 = pin.neutral(model) + 0.3
    pin.framesForwardKinematics(model, data, q0)
    centre = data.oMf[frame].translation.copy()
    rotation = data.oMf[frame].rotation.copy()
    position = centre + np.hstack([0.05 * np.cos(w * t) - 0.05, 0.05 * np.sin(w * t), 0 * t])
    velocity = np.hstack([-0.05 * w * np.sin(w * t), 0.05 * w * np.cos(w * t), 0 * t])
    acceleration = np.hstack([-0.05 * w**2 * np.cos(w * t), -0.05 * w**2 * np.sin(w * t), 0 * t])
    orientation = np.tile(rotation, (samples, 1, 1))
    task = TaskTrajectory(position, velocity, acceleration, orientation, np.zeros((samples, 3)), np.zeros((samples, 3)))
    load = np.zeros((samples, 6))

    def ours() -> object:
        return inverse_dynamics(robot, task, load, "numeric")

    def loop() -> None:
        q = q0.copy()
        target = pin.SE3(rotation, np.zeros(3))
        for k in range(samples):
            target.translation = position[k]
            for _ in range(20):  # Newton on the 6-D pose error
                pin.framesForwardKinematics(model, data, q)
                error = pin.log6(data.oMf[frame].actInv(target)).vector
                if np.linalg.norm(error) < 1e-12:
                    break
                jacobian = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL)
                q = pin.integrate(model, q, np.linalg.solve(jacobian, error))
            jacobian = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL_WORLD_ALIGNED)
            twist = np.concatenate([velocity[k], np.zeros(3)])
            v = np.linalg.solve(jacobian, twist)
            pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
            drift = pin.getFrameClassicalAcceleration(model, data, frame, pin.LOCAL_WORLD_ALIGNED).vector
            a = np.linalg.solve(jacobian, np.concatenate([acceleration[k], np.zeros(3)]) - drift)
            pin.rnea(model, data, q, v, a)

    def best(function: Callable[[], object]) -> float:
        function()
        shortest, start = np.inf, time.perf_counter()
        while time.perf_counter() - start < seconds:
            tic = time.perf_counter()
            function()
            shortest = min(shortest, time.perf_counter() - tic)
        return samples / shortest

    ours_rate, loop_rate = best(ours), best(loop)
    return ours_rate, loop_rate, ours_rate / loop_rate


def compare(problem: str, seeds: list[int], peers: list[str]) -> list[str]:
    """One problem's table rows (Markdown): per seed, our time and best energy, each peer's, and whether ours is at or
    below every peer's."""
    robot_name, path_file, cell_file = PROBLEMS[problem]
    robot = load_robot(robot_name)
    if cell_file is not None:
        robot = equip(robot, load_cell(ROOT / cell_file))
    path = load_path(ROOT / path_file)
    space = default_space(robot, half_turn=path.half_turn_symmetric())
    settings = EvaluatorSettings(threads=1, workers=1)
    rows = []
    optimize_placement(robot, path, space=space, evaluation=settings,  # loads the compiled kernels: not timed
                       settings=SearchSettings(max_generations=1, worst=False))
    for seed in seeds:
        tic = time.process_time()
        result = optimize_placement(robot, path, space=space, evaluation=settings,
                                    settings=SearchSettings(seed=seed, worst=False))
        seconds = time.process_time() - tic
        assert result.best is not None
        ours = result.best.detail.value
        found, unprinted = {}, np.inf
        for peer in peers:
            with Evaluator(robot, path, settings) as evaluator:
                budget = (run_de(evaluator, space, seconds, seed, DE_POPULATIONS[peer]) if peer in DE_POPULATIONS
                          else run_optuna(evaluator, space, seconds, seed, peer))
                found[peer], unprinted = as_printed(evaluator, space, budget.best_x), min(unprinted, budget.best)
        gap = (ours - min(found.values())) / ours  # > 0: a peer found less energy than ours
        verdict = "yes" if gap <= 0 else f"NO, by {gap:.1e} (relative)"
        rows.append(f"| {problem} | {seed} | {seconds:.2f} | {ours:.7f} | "
                    + " | ".join(f"{found[p]:.7f}" for p in peers) + f" | {unprinted:.7f} | {verdict} |")
        print(rows[-1], flush=True)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--problems", nargs="+", choices=sorted(PROBLEMS), default=list(PROBLEMS))
    parser.add_argument("--seeds", type=int, nargs="+", default=list(range(10)))
    parser.add_argument("--peers", nargs="+", choices=PEERS, default=list(PEERS))
    parser.add_argument("--chain-seconds", type=float, default=2.0)
    args = parser.parse_args()
    header = ("| problem | seed | CPU s | ours | " + " | ".join(args.peers) + " | peers unprinted | ours <= all |\n"
              + "|---" * (6 + len(args.peers)) + "|")
    print("Least energy (J) of the best feasible placement found, at the path's own sampling, as printed (0.01 mm, "
          "0.01°; 'peers unprinted': the least a peer found before printing); each peer is given the CPU time of our "
          "search (s), in this process")
    print(header)
    for problem in args.problems:
        compare(problem, args.seeds, args.peers)
    if args.chain_seconds > 0:
        ours_rate, loop_rate, ratio = chain_against_loop(args.chain_seconds)
        print(f"UR5 kinematics + RNEA, one core: our batched chain {ours_rate:,.0f} samples/s, a plain Pinocchio "
              f"per-sample loop (Newton IK, rnea) {loop_rate:,.0f} samples/s: {ratio:.1f}x")


if __name__ == "__main__":
    from results import recorded  # this run's section of benchmarks/RESULTS.md

    keep_freed_memory()  # as the command line does: the batches\' freed memory kept for the next ones
    with recorded("peers"):
        main()
