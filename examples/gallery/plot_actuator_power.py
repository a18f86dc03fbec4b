"""
Where the energy goes
=====================

One placement evaluated in detail (:meth:`placement.Evaluator.detail`): each slider's electric power along
the groove, and the energy's parts per actuator — Joule losses, the inductive part and the back-EMF part,
whose sum is the electric energy, beside the mechanical (shaft) energy. Under the default regeneration
policy (``clip``) braking power is burnt in each drive, so only the positive power is paid for.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import placement

try:
    EXAMPLES = Path(__file__).resolve().parents[1]  # examples/, whatever the working folder
except NameError:  # run by the documentation's build, in examples/gallery/ without __file__
    EXAMPLES = Path.cwd().parent

robot = placement.load_robot("orthoglide")
path = placement.load_path(EXAMPLES / "rect.yaml")
detail = placement.Evaluator(robot, path).detail(np.array([0.0, 0.0, -0.033, 0.0, 0.0, 0.0]))

names = [actuator.joint for actuator in robot.actuators]
energy = detail.energy
print(f"electric energy {energy.total_J:.4f} J")
for i, name in enumerate(names):
    print(f"  {name}: {energy.per_actuator_J[i]:.4f} J (Joule {energy.joule_J[i]:.4f}, inductive "
          f"{energy.inductive_J[i]:.4f}, back-EMF {energy.back_emf_J[i]:.4f}; shaft {energy.mechanical_J[i]:.4f})")

figure, (power_axes, parts_axes) = plt.subplots(1, 2, figsize=(10, 3.8), constrained_layout=True)
for i, name in enumerate(names):
    power_axes.plot(detail.samples.t_s, detail.power_W[:, i], label=name)
power_axes.set(xlabel="t (s)", ylabel="electric power (W)", title="power along the path")
power_axes.legend()
bottom = np.zeros(len(names))
for part in ("joule", "inductive", "back_emf"):
    values = getattr(energy, f"{part}_J")
    parts_axes.bar(names, values, bottom=bottom, label=part.replace("_", "-"))
    bottom += values
parts_axes.set(ylabel="energy (J)", title="energy per actuator, by part")
parts_axes.legend()
plt.show()
