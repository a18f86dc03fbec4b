"""The command line keeps the memory its batches free for the next ones (placement.cli.memory), and the library
leaves a host program's memory settings alone: under glibc, a batch like the last faults in few new pages once the
command line has raised malloc's thresholds, and some 7000 (28 MB, every array of a megabyte or more) with glibc's
defaults, which an Evaluator keeps."""

import json
import subprocess
import sys

import pytest

from tests.support.paths import ROOT

MEASURE = """
import json, resource, numpy as np
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path import load_path
from placement import load_robot
evaluator = Evaluator(load_robot("orthoglide"), load_path("examples/rect.yaml"), EvaluatorSettings(threads=1))
rng = np.random.default_rng(0)
placements = np.zeros((64, 6))
placements[:, :3], placements[:, 3] = rng.uniform(-0.02, 0.02, (64, 3)), rng.uniform(-1.0, 1.0, 64)

def faults_per_batch(offset):
    evaluator.evaluate(placements + offset)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for step in range(1, 6):
        evaluator.evaluate(placements + offset + step * 1e-9)
    return (resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before) / 5

library = faults_per_batch(0.0)
from placement.cli.memory import keep_freed_memory
kept = keep_freed_memory()
print(json.dumps({"library": library, "kept": kept, "cli": faults_per_batch(1e-6)}))
"""


def test_the_command_line_keeps_freed_memory_and_the_library_does_not():
    run = subprocess.run([sys.executable, "-c", MEASURE], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    measured = json.loads(run.stdout.strip().splitlines()[-1])
    if not measured["kept"]:
        pytest.skip("the C library has no mallopt (not glibc)")
    assert measured["cli"] < 1000, measured
    assert measured["library"] > 3 * max(measured["cli"], 100), measured
