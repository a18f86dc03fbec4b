"""The reference posture of an estimated serial arm: damped least squares that bring its tool to a point, pointing
down for a pose task (its yaw free), from a start posture and then from seeded ones, keeping a well-conditioned
one away from the joint limits (the rules: :mod:`placement.workshop.estimates`)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from placement.robot.tool import find_frame

REFERENCE_SEEDS = 32
GOOD_CONDITION, MAX_CONDITION = 20.0, 100.0
GOOD_LIMIT_MARGIN = 0.1  # a good reference posture keeps every joint this share of its range from its limits
DAMPING, MAX_STEP_RAD = 1e-6, 0.3  # of the least-squares steps towards a reference posture
DOWN = np.array([0.0, 0.0, -1.0])


class PostureSolver:
    """Damped least squares that bring the tool to a point, pointing down for a pose task (yaw free)."""

    def __init__(self, model: pin.Model, tool: str, pose: bool, reach_m: float) -> None:
        self.model, self.data, self.pose, self.reach_m = model, model.createData(), pose, reach_m
        self.frame_id = find_frame(model, tool)

    def from_full(self, full: pin.Model, q_full: np.ndarray) -> np.ndarray:
        """A configuration of this model from one of the full model (joints matched by name)."""
        q = pin.neutral(self.model)
        for j in range(1, self.model.njoints):
            q[self.model.joints[j].idx_q] = q_full[full.joints[full.getJointId(self.model.names[j])].idx_q]
        return np.clip(q, self.model.lowerPositionLimit, self.model.upperPositionLimit)

    def to_full(self, full: pin.Model, q_full: np.ndarray, q: np.ndarray) -> np.ndarray:
        """``q_full`` with this model's joints set from ``q``."""
        out = q_full.copy()
        for j in range(1, self.model.njoints):
            out[full.joints[full.getJointId(self.model.names[j])].idx_q] = q[self.model.joints[j].idx_q]
        return out

    def reference(self, target: np.ndarray, q0: np.ndarray, rng: np.random.Generator) -> np.ndarray | None:
        """From ``q0``, then seeded postures: the first solution conditioned below GOOD_CONDITION, else the best."""
        low = np.maximum(self.model.lowerPositionLimit, -np.pi)
        high = np.minimum(self.model.upperPositionLimit, np.pi)
        best, best_condition = None, MAX_CONDITION
        for seed in [q0, *(rng.uniform(low, high) for _ in range(REFERENCE_SEEDS))]:
            q = self.solve(target, seed)
            if q is None:
                continue
            condition = self.condition(q)
            if condition < GOOD_CONDITION and self.limit_margin(q) >= GOOD_LIMIT_MARGIN:
                return q
            if condition < best_condition:
                best, best_condition = q, condition
        return best

    def limit_margin(self, q: np.ndarray) -> float:
        """The least distance of a joint to its nearer limit, as a share of its range (1 without limits)."""
        low, high = self.model.lowerPositionLimit, self.model.upperPositionLimit
        bounded = np.isfinite(low) & np.isfinite(high) & (high > low)
        shares = np.minimum(q - low, high - q)[bounded] / (high - low)[bounded]
        return float(shares.min()) if len(shares) else 1.0

    def condition(self, q: np.ndarray) -> float:
        """Condition number of the task Jacobian, linear rows divided by the chain length."""
        jacobian = pin.computeFrameJacobian(self.model, self.data, q, self.frame_id, pin.LOCAL_WORLD_ALIGNED).copy()
        jacobian[:3] /= self.reach_m
        return float(np.linalg.cond(jacobian if self.pose else jacobian[:3]))

    def solve(self, target: np.ndarray, q: np.ndarray, iterations: int = 300) -> np.ndarray | None:
        """A configuration within the limits with the tool at ``target`` (and pointing down), or None."""
        q = q.copy()
        for _ in range(iterations):
            pin.framesForwardKinematics(self.model, self.data, q)
            error, jacobian = self._error(q, target)
            if np.linalg.norm(error) < 1e-10:
                return q
            step = jacobian.T @ np.linalg.solve(jacobian @ jacobian.T + DAMPING * np.eye(len(error)), error)
            step *= min(1.0, MAX_STEP_RAD / max(float(np.abs(step).max()), 1e-300))
            q = np.clip(pin.integrate(self.model, q, -step), self.model.lowerPositionLimit, self.model.upperPositionLimit)
        return None

    def _error(self, q: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        placement = self.data.oMf[self.frame_id]
        if not self.pose:
            jacobian = pin.computeFrameJacobian(self.model, self.data, q, self.frame_id, pin.LOCAL_WORLD_ALIGNED)
            return placement.translation - target, jacobian[:3]
        x = placement.rotation[:, 0] - placement.rotation[2, 0] * np.array([0.0, 0.0, 1.0])
        if np.linalg.norm(x) < 1e-6:  # the tool's x axis is vertical: take its y axis for the yaw
            x = np.cross(placement.rotation[:, 1], DOWN)
        x /= np.linalg.norm(x)
        wanted = pin.SE3(np.column_stack([x, np.cross(DOWN, x), DOWN]), target)
        offset = placement.actInv(wanted)
        jacobian = pin.computeFrameJacobian(self.model, self.data, q, self.frame_id, pin.LOCAL)
        return -pin.log6(offset).vector, pin.Jlog6(offset.inverse()) @ jacobian
