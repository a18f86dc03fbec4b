"""An Evaluator keeps the memory its batches free for the next ones (placement.evaluation.memory): under glibc, a
batch like the last faults in few new pages (glibc's defaults fault in some 7000 per batch of 64 placements of the
rectangle again, 28 MB, every array of a megabyte or more)."""

import resource

import numpy as np
import pytest

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.evaluation.memory import keep_freed_memory
from placement.path import load_path


def test_a_batch_like_the_last_reuses_its_memory(orthoglide):
    evaluator = Evaluator(orthoglide, load_path("examples/rect.yaml"), EvaluatorSettings(threads=1))
    rng = np.random.default_rng(0)
    placements = np.zeros((64, 6))
    placements[:, :3], placements[:, 3] = rng.uniform(-0.02, 0.02, (64, 3)), rng.uniform(-1.0, 1.0, 64)
    evaluator.evaluate(placements)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for step in range(1, 6):
        evaluator.evaluate(placements + step * 1e-9)
    faults = (resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before) / 5
    if not keep_freed_memory():  # asked after the batches: the Evaluator is what asks for it
        pytest.skip("the C library has no mallopt (not glibc)")
    assert faults < 1000
