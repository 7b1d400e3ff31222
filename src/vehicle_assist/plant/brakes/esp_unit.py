"""ESP hydraulic unit: per circuit a switching (isolation) valve USV and a high-pressure (suction) valve HSV,
per wheel an inlet valve EV and an outlet valve AV, a low-pressure accumulator LPA, and one return-pump
motor (brake_assist.md 2; paper 002 P6-P8).

The ECU commands a *wheel mode*; which valves and pump that means is the data table ``VALVE_TABLE``
(spec 2, one row per mode, checked by a test). A circuit's USV is closed if any of its wheels' modes
closes it, its HSV open if any opens it; the pump runs if any wheel's mode runs it (one motor).

Wheel pressure (simplified model of spec 2; p_src = p_mc front, p_prop(p_mc) rear):

    N  : dp/dt = (p_src - p)/tau_line
    B  : dp/dt = build rate of the pressure source (pump) up to p_lim   (+ USV check valve, below)
    BP : dp/dt = duty * build rate (pulsed inlet)
    BPM: dp/dt = min(duty*(p_src - p)/tau_line, duty*G_pump), >= 0 (plain ABS: pulsed re-build from the master
         cylinder; assumed: the inlet pulses give the same mean gradient as the pump's BP)
    H, HI: dp/dt = 0           (HI: hold with the circuit isolated, during HBA)
    H, BPM with p > p_src: as N (the inlet valve's return check valve; the USV is open in these rows)
    D  : dp/dt = -(p - p_LPA)/tau_dump
    T  : dp/dt = -min(G_exit, (p - p_src)/tau_line) while p > p_src, else 0 (inlet closed: no inflow; row T)
         - the ECU hands a wheel back to N once it is within 1 bar of p_src (spec 2 row T: 'then mode N')

USV check valve: with the inlet fully open (B) a driver pressure above the wheel's still flows in, so a
dead pump never leaves the wheel below the driver's pressure (in BP the pulsed inlet is the bottleneck:
the spec's duty*G_pump) (issue #9: "pump failed -> driver pressure still
reaches the wheels"). The *pressure source* is replaceable: ``SOURCE_RETURN_PUMP`` (rate G_pump up to the
relief p_lim) here, ``SOURCE_ACCUMULATOR`` (orifice-like fill from an accumulator at p_acc,
rate (p_acc - p)/tau_acc) for the EHB of paper 004.
"""
from __future__ import annotations

import numba as nb
import numpy as np

# wheel modes (rows of VALVE_TABLE)
N, B, HI, H, D, BP, BPM, T = range(8)
MODES = ("N", "B", "HI", "H", "D", "BP", "BPM", "T")
MODE_DOC = {
    "N": "normal: driver pressure to the wheel",
    "B": "active build (HBA): pump raises the wheel pressure above the driver's",
    "HI": "hold with the circuit isolated (HBA active)",
    "H": "hold, plain ABS (circuit open to the master cylinder)",
    "D": "dump into the low-pressure accumulator, pump returns the fluid",
    "BP": "pulsed re-build by the pump (HBA)",
    "BPM": "pulsed re-build from the master cylinder (plain ABS)",
    "T": "termination ramp-out toward the driver's pressure",
}
# columns: USV closed, HSV open, EV (inlet) open (0.5 = pulsed), AV (outlet) open, pump on
VALVE_COLUMNS = ("usv_closed", "hsv_open", "inlet_open", "outlet_open", "pump_on")
VALVE_TABLE = np.array([
    # USVc HSVo  EV   AV  pump
    [0.0, 0.0, 1.0, 0.0, 0.0],  # N   spec 2 row N
    [1.0, 1.0, 1.0, 0.0, 1.0],  # B   spec 2 row B (paper P6: switching valve closed, HSV open, pump on)
    [1.0, 0.0, 0.0, 0.0, 0.0],  # HI  spec 2 row H, HBA (paper P7: inlet and HSV closed, pump off)
    [0.0, 0.0, 0.0, 0.0, 0.0],  # H   spec 2 row H, plain ABS
    [0.0, 0.0, 0.0, 1.0, 1.0],  # D   spec 2 row D (paper P7: outlet and switching valve open, pump returns)
    [1.0, 1.0, 0.5, 0.0, 1.0],  # BP  spec 2 row BP (paper P7: USV, AV closed, HSV open, pump on, EV pulsed)
    [0.0, 0.0, 0.5, 0.0, 1.0],  # BPM plain-ABS pulsed build from the master cylinder (standard ESP practice)
    [1.0, 0.0, 0.0, 1.0, 1.0],  # T   spec 2 row T (paper P8: inlet closed, outlet open, pump returns surplus)
])
SOURCE_RETURN_PUMP, SOURCE_ACCUMULATOR = 0, 1
SOURCES = {"return_pump": SOURCE_RETURN_PUMP, "accumulator": SOURCE_ACCUMULATOR}
SETTLED_PA = 1.0e5  # "|p_w - p_src| < 1 bar" (spec 3, TERMINATING; criterion 7)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def source_rate_pa_per_s(kind, p_wheel, rate_pa_per_s, limit_pa, accumulator_pa, accumulator_tau_s, working):
    """Build rate the pressure source gives a wheel at pressure p_wheel (0 if the source has failed)."""
    if not working:
        return 0.0
    if kind == SOURCE_ACCUMULATOR:
        return max(accumulator_pa - p_wheel, 0.0) / accumulator_tau_s
    return rate_pa_per_s if p_wheel < limit_pa else 0.0


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_pressure_step(mode, p, p_src, dt, tau_line_s, source_rate, limit_pa, duty_frac, tau_dump_s, p_lpa,
                        exit_rate_pa_per_s, pulse_rate_pa_per_s):
    """Wheel-cylinder pressure after one step in ``mode`` (semi-analytic where a lag is involved)."""
    follow = p + (p_src - p) * min(dt / tau_line_s, 1.0)
    if mode == N:
        return follow
    if mode == B or mode == BP:
        rate = source_rate if mode == B else duty_frac * source_rate
        built = min(p + rate * dt, max(limit_pa, p))
        if mode == B and p_src > p:  # USV check valve: the driver's pressure still reaches the (open) wheel
            built = max(built, follow)
        return built
    if (mode == H or mode == BPM) and p > p_src:
        # switching valve open: the inlet valve's return check valve lets a wheel pressure above the driver's back
        # to the master cylinder (std: Bosch Automotive Handbook, ABS modulator), so an easing driver lowers it
        return follow
    if mode == BPM:
        return p + min(duty_frac * max(p_src - p, 0.0) * min(dt / tau_line_s, 1.0), duty_frac * pulse_rate_pa_per_s * dt)
    if mode == HI or mode == H:
        return p
    if mode == D:
        return p_lpa + (p - p_lpa) * max(1.0 - dt / tau_dump_s, 0.0)
    # T (row T: inlet closed, outlet open): the wheel can only lose fluid into the LPA, at the ramp-out gradient,
    # down to the driver's pressure; with the inlet closed nothing flows in, so a wheel at or below the driver's
    # pressure holds (the ECU then hands it back to mode N, functions/esp.py ARBITRATION row T_DONE)
    if p > p_src:
        return p - min(exit_rate_pa_per_s * dt, (p - p_src) * min(dt / tau_line_s, 1.0))
    return p
