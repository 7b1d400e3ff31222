"""Scripted driver: pedals, gear lever, hand park valve and steering as breakpoint tables over time.

The scenario's ``[driver]`` tables (validated, monotonic time breakpoints; pedals interpolated linearly,
lever and valve as steps) are evaluated at the sampling tick. A scenario event may override any input
from its instant on. Closed-loop driver models (speed-keeping, curve driver, path follower) will sit
beside this one with the same output vector.
"""
from __future__ import annotations

import numba as nb

from vehicle_assist.core.tables import interp

# driver inputs (index into the input and override arrays)
IN_ACCELERATOR, IN_BRAKE_PEDAL, IN_GEAR_LEVER, IN_HAND_VALVE, IN_STEERING = range(5)
INPUTS = ("accelerator", "brake_pedal", "gear_lever", "hand_valve", "steering")


@nb.njit(cache=True, nogil=True, error_model="numpy")
def driver_inputs(s, t, override_on, override_value, out):
    """Scripted driver: pedal, lever and valve tables over time, unless an event overrode them."""
    out[IN_ACCELERATOR] = interp(s.driver_accelerator_x, s.driver_accelerator_y, s.driver_accelerator_n,
                                      s.driver_accelerator_extrap, s.driver_accelerator_interp, t)
    out[IN_BRAKE_PEDAL] = interp(s.driver_brake_pedal_x, s.driver_brake_pedal_y, s.driver_brake_pedal_n,
                                      s.driver_brake_pedal_extrap, s.driver_brake_pedal_interp, t)
    out[IN_GEAR_LEVER] = interp(s.driver_gear_lever_x, s.driver_gear_lever_y, s.driver_gear_lever_n,
                                     s.driver_gear_lever_extrap, s.driver_gear_lever_interp, t)
    out[IN_HAND_VALVE] = interp(s.driver_hand_valve_x, s.driver_hand_valve_y, s.driver_hand_valve_n,
                                     s.driver_hand_valve_extrap, s.driver_hand_valve_interp, t)
    out[IN_STEERING] = interp(s.driver_steering_x, s.driver_steering_y, s.driver_steering_n,
                                   s.driver_steering_extrap, s.driver_steering_interp, t)
    for i in range(out.shape[0]):
        if override_on[i]:
            out[i] = override_value[i]
