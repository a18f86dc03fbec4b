"""A motion of ur5_positioner's table used by its tests."""

import numpy as np

# near the search's optimum on the weld (phi, then tilt's and rotate's knots, deg): the table tilting towards the UR5
# and turning the seam under the torch; x, y, z stay 0
TURNING = np.radians([0.0, 0.0, 0.0, -120.0, 0.0, 0.0, -10.0, -25.0, -20.0, 290.0, 140.0, -20.0])
TURNING[:3] = 0.0
