"""The drives along a motion: the motor trace, the electric energy, regeneration policies and the duty cycle.

- :mod:`placement.energy.trace`: the drive equations, once: motor speed, torque and current, and their path bounds;
- :mod:`placement.energy.integration`: the electric energy, integrated interval by interval;
- :mod:`placement.energy.regeneration`: what happens to braking energy (a plug-in family);
- :mod:`placement.energy.duty`: the RMS torque against the rating, and the cycles per hour.
"""
