"""ESP controller: one ECU hosting ABS and HBA (blowout compensation next) on one hydraulic unit, arbitrating
per wheel through a table (issue #9). Runs every ``esp.period_s`` on the measurement record only.

Per period:
1. Reference speed from the wheel speeds: v_ref = max(max_i v_w,i, v_ref - (|a_x,meas| + margin)*dt)
   (the car cannot slow faster than the accelerometer says; std ABS practice, Bosch Handbook). Wheel-signal
   plausibility (``reference_plausibility_flag``): a wheel that, while the driver does not brake, turns faster than
   the median of the other three by ``reference_implausible_frac`` for ``reference_implausible_time_s`` (a much
   smaller rolling radius: blown or deflated tire, compact spare) is left out of the max until, again unbraked, it
   is within that band for the same time; while braking the decision is frozen, so an ABS-recovering wheel (briefly
   much faster than its slipping neighbours) is never taken for one. The test is the blowout compensation's
   wheel-speed signature (``blowout_compensation._candidate_ws``, base = the median of the others). While braking
   (``reference_braking_plausibility_flag``) the reference rises at most at max(a_x, 0) + RISE_MARGIN (a braked car
   cannot speed up) and a wheel above that bound by the same band for the same time, with no ABS activity for
   ``reference_braking_abs_quiet_time_s``, is left out (an ABS-recovering wheel returns to the vehicle speed from
   below): a pedal within ~0.1 s of a blowout comes before the unbraked decision (finding F4b). Past the pedal onset
   (``reference_braking_rise_limit_flag``) ONE wheel lifts the reference at most at a_x + ``reference_braking_rise_
   margin_mps2`` whatever its valves do (ABS practice: the reference's rise is limited to the largest possible vehicle
   acceleration; an ABS-dumped flat front spinning up to its smaller radius carried it 25.2 -> 32.6 m/s in 0.3 s,
   finding G8); the second fastest wheel lifts it freely (two wheels agreeing show the car's speed). A lone fast wheel
   with valve activity is judged too when two other wheels have been unbraked (pressure estimate below
   plausibility_pressure) for ``reference_braking_abs_quiet_time_s`` (``reference_unbraked_outlier_flag``): an
   unbraked wheel turns at the car's speed (K5: a rear blown at the pedal held the reference over a car whose four
   wheels the ABS had dumped to 1 bar).
2. Pressure-sensor health: valid flag from the sensor, plus plausibility against the brake-light switch
   (switch on with p_mc below ``plausibility_pressure`` for ``plausibility_time``, or off with p_mc above it,
   latches a fault).
3. ABS per wheel (functions/abs.py; with ``abs_hold_limit_flag`` - shipped 0, a candidate - a hold above L_HOLD whose
   wheel does not re-accelerate ends in a dump step, ``abs_hold_limit``), then select-low on the rear axle (both rear
   wheels follow the more critical one) and the yaw-moment build-up delay (GMA) on split-mu: while ABS cycles on one front wheel
   only, the other front wheel builds in short pulses (``gma_pulse_s`` every ``gma_cycle_s``) for
   ``gma_duration_s``, so the yaw moment of the brake-force difference grows slowly enough for the driver;
   for the rest of the stop the yaw rate limits it (yaw toward the high-mu side above ``yaw_hold_rate``:
   hold that wheel, above ``yaw_dump_rate``: dump it), as ESP units do on split-mu (Bosch Handbook, std).
   The GMA limits the high-mu wheel's pressure relative to the low-mu wheel's: during an assist whose pump lifted the
   other front above the driver's pressure, the GMA's wheel follows it up to (not past) that pressure
   (``gma_follow_flag``; a noise-split HBA-onset dump arms the GMA on a dry road, and the driver's-pressure cap of
   ``gma_hba_flag`` then held one front at 27-60 bar against 83 bar on the other for the whole stop).
4. HBA (functions/brake_assist.py), if enabled, available only while ABS and the pump are healthy.
5. Arbitration: wheel valve mode = ``ARBITRATION[hba mode][wheel request]`` (data below).
6. The ECU's wheel-pressure estimate (its model of the unit, nominal data) tells TERMINATING when the
   wheels are back at the driver's pressure. In mode N it takes the source at once; ``pressure_estimate_line_flag``
   >= 2 (2 shipped) keeps a line-lag estimate alongside (A_P_LINE) for the lock level stored at an ABS dump's start, 3
   (candidate, not shipped) also compares the braking rule's ceiling on it, and ``lock_level_line_flag`` reads braking_lock_floor's and the
   GMA's front lock levels from it (tire_blowout_findings.md I9, I11, J2).
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import log_event
from vehicle_assist.functions import abs as abs_fn
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.functions import brake_assist as hba
from vehicle_assist.plant.brakes.master_cylinder import proportioned_pa

# wheel valve modes (the ESP unit's table rows; same order as plant/brakes/esp_unit.py MODES)
W_N, W_B, W_HI, W_H, W_D, W_BP, W_BPM, W_T = range(8)
WHEEL_MODES = ("N", "B", "HI", "H", "D", "BP", "BPM", "T")
# wheel requests: the ABS modes, plus the two phases of the yaw-moment build-up delay
R_OFF, R_HOLD, R_DUMP, R_BUILD, R_GMA_HOLD, R_GMA_PULSE = range(6)
REQUESTS = ("OFF", "HOLD", "DUMP", "BUILD", "GMA_HOLD", "GMA_PULSE")
# ARBITRATION[hba mode][request] -> wheel valve mode (paper P6-P8, spec 2-3):
#   no HBA: ABS on the driver's pressure (hold with the circuit open, pulsed build from the master);
#   HBA active: no ABS request -> active build by the pump; ABS hold isolates the circuit; re-build by the pump;
#   HBA terminating, wheel above the driver's pressure: ramp-out, except that a dump request (lock threatened)
#   always wins; HBA terminating, wheel back at (within 1 bar of) or below the driver's pressure: the wheel's
#   ramp-out is over (spec 2 row T "then mode N"), it is the driver's again with plain ABS (row T_DONE = INACTIVE).
ARBITRATION = np.array([
    # OFF   HOLD  DUMP  BUILD  GMA_H  GMA_P
    [W_N, W_H, W_D, W_BPM, W_H, W_BPM],  # INACTIVE
    [W_B, W_HI, W_D, W_BP, W_HI, W_BP],  # ACTIVE
    [W_T, W_T, W_D, W_T, W_T, W_T],      # TERMINATING (wheel above the driver's pressure)
    [W_N, W_H, W_D, W_BPM, W_H, W_BPM],  # T_DONE: TERMINATING, this wheel's ramp-out complete
    [W_N, W_H, W_D, W_BPM, W_H, W_BPM],  # A_DRIVER: ACTIVE, the driver alone reaches this circuit's lock limit
], dtype=np.int64)
ARBITRATION_ROWS = ("INACTIVE", "ACTIVE", "TERMINATING", "T_DONE", "A_DRIVER")
T_DONE, A_DRIVER = 3, 4
CIRCUIT = np.array([0, 1, 1, 0], dtype=np.int64)  # X-split: circuit 1 = fl + rr, circuit 2 = fr + rl
# A_DRIVER (issue #9 review, "never worse than no assist"): the pump is only the pressure source where it has to
# lift the wheel above the driver (paper P2/P6: "raises line pressure up to the ABS control level"). Where ABS finds
# the lock limit below the driver's own pressure, the circuit stays open to the master cylinder and ABS works on
# the driver's pressure exactly as without HBA; isolating it, pumping the rear above its proportioned pressure and
# re-building by the pump cost up to 0.28 m of stopping distance (mu 0.5 dry, 200 N in 7 ms from 100 km/h).
RAMP_SETTLED_PA = 1.0e5  # "|p_w - p_src| < 1 bar" ends a wheel's ramp-out (spec 3 TERMINATING, criterion 7)
PRIORITY = np.array([0, 2, 3, 1], dtype=np.int64)  # select-low: DUMP > HOLD > BUILD > OFF
# BLOWOUT_ARBITRATION[compensation request][wheel mode after ABS/HBA] -> wheel mode (paper 004 P7, issue #10):
#   BUILD (accumulator build for the valve time) and HOLD give way to ABS (hold/dump/pulsed build: lock threat)
#   and to HBA's own build; RELEASE (the blown wheel is not braked) always dumps; PULSE = closed-loop build.
BLOWOUT_ARBITRATION = np.array([
    # N     B     HI    H     D     BP    BPM    T
    [W_N, W_B, W_HI, W_H, W_D, W_BP, W_BPM, W_T],    # NONE
    [W_B, W_B, W_HI, W_H, W_D, W_BP, W_BPM, W_B],    # BUILD
    [W_HI, W_B, W_HI, W_H, W_D, W_BP, W_BPM, W_HI],  # HOLD
    [W_D, W_D, W_D, W_D, W_D, W_D, W_D, W_D],        # RELEASE
    [W_BP, W_B, W_BP, W_H, W_D, W_BP, W_BPM, W_BP],  # PULSE
], dtype=np.int64)
ABS_ACTIVE_WINDOW_S = 0.3  # "ABS active on a wheel = a hold or dump in the last 0.3 s" (spec 4.3)
ABS_DECEL_WINDOW_N = 3  # ABS wheel deceleration outside DUMP (esp.abs_signal_filter_flag): least-squares slope over
#   the last 3 ESP periods = (v_k-2 - v_k)/(2*dt): white wheel-speed noise sigma*r enters as sigma*r/(sqrt(2)*dt), half
#   the one-period difference's sqrt(2)*sigma*r/dt (SUV at 0.2 rad/s: 10 vs 20 m/s^2 rms against A_DUMP = 30 m/s^2,
#   3 vs 1.5 sigma); 1 period lag. Not longer: 4 samples (1.5 periods) took 0.14 m off HBA never-worse points
#   (tests/functions/test_hba_gma_and_rebuild.py P147). Not while in DUMP: the exit test keeps the one-period
#   difference - the slope's lag there lengthened every dump (ABS stop 100 km/h dry, 300 N: 39.7 -> 41.95 m)
ABS_LOG_CAP = 60  # ABS mode changes logged per wheel (the event buffer is shared; all are in the trace)

# controller state vector (named indices)
C_V_REF, C_STARTED, C_IMPLAUSIBLE_S, C_SENSOR_LATCH, C_GMA_START, C_GMA_WHEEL, C_T, C_SENSOR_OK, C_ABS_OK, \
    C_HBA_AVAILABLE, C_SOURCE_C1, C_SOURCE_C2, C_GMA_BLOCK, C_PUMPED_C1, C_PUMPED_C2, C_REF_EXCLUDED, \
    C_REF_PERSIST_S, C_BRAKED_S, C_GMA_PRE, C_LOCK_P0, C_LOCK_P1, C_LOCK_REJ = range(22)
SRC_UNDECIDED, SRC_PUMP, SRC_DRIVER = 0.0, 1.0, 2.0  # per circuit during an assist (C_SOURCE_C1/C2)
CTL_SIZE = 22
# C_LOCK_P0/1: each front's ABS lock level while the brake is on - its estimated pressure when ABS last began a dump
# (A_P_LINE with lock_level_line_flag; 0 none yet, -1 skip the next dump; cleared when the brake is released and, with
# gma_rejected_split_quiet_flag, after 0.3 s of ABS quiet on that front); read by gma_rejected_split_flag only.
# C_LOCK_REJ = 1 + the rejected front whose lock level was reset at its rejection (gma_rejected_split_flag)
# C_GMA_PRE = 1 + the front wheel whose split-mu GMA was running when a blowout detection on the OTHER front made it
# the compensating wheel and gma_blown_front_flag ended that GMA (0 none; gma_rejected_pre_flag); cleared with the block
# C_BRAKED_S: time since the brake-light switch came on (0 while off)
# C_REF_EXCLUDED: wheel the reference speed leaves out as implausibly fast (-1 none); C_REF_PERSIST_S: how long the
# pending change (a new fast wheel, or the excluded one plausible again) has persisted
# C_PUMPED_C1/C2: 1 once the pump served the circuit in this assist (source SRC_PUMP), kept through TERMINATING
# C_GMA_BLOCK = 1 + the front wheel the blowout compensation brakes (0 none): its ABS activity is caused by the
# compensation's own build, not by a split-mu road, so it does not start the GMA; kept after the compensation
# ends until that wheel's ABS is OFF again (independent review of issue #10: a rejected false TPMS detection
# while braking latched the GMA on the healthy wheel it had released, 3-10 bar for ~1 s, 1.12 m off the lane)
# per-wheel state (rows fl, fr, rl, rr)
A_MODE, A_BUILD_S, A_VW_PREV, A_SINCE_HD_S, A_LOGGED, A_SLIP, A_DECEL, A_REQUEST, A_WHEEL_MODE, A_P_EST, \
    A_INLET_OPEN_S, A_ABS_QUIET_S, A_VALVE_QUIET_S, A_HOLD_S, A_HOLD_SUM, A_HOLD_PREV, A_P_LINE, A_UNBRAKED_S = range(18)
WHEEL_STATE_SIZE = 18
# A_UNBRAKED_S: time since the wheel's estimated pressure (the higher of A_P_EST and A_P_LINE) was last at or above
# plausibility_pressure (the brake not applied below it): a wheel unbraked that long rolls at the car's speed
# (reference_unbraked_outlier_flag, braking_outlier)
# A_P_LINE: the same estimate with mode N through the line lag (pressure_estimate_line_flag >= 2: kept alongside A_P_EST
# and read where a dump's start is stored as a lock level - S_P_PREDUMP, and with lock_level_line_flag braking_lock_floor's
# level and C_LOCK_P0/1 - and where the wheel is compared with those levels)
# A_HOLD_S / A_HOLD_SUM: time and slip integral of the present window of an ABS hold above the hold slip; A_HOLD_PREV:
# the previous window's mean slip (-1: none yet) - esp.abs_hold_limit_flag, abs_hold_limit
# A_ABS_QUIET_S: time since the wheel's ABS mode was last other than OFF (hold, dump or build); A_VALVE_QUIET_S: time
# since its ABS mode was last other than OFF or its valve mode other than N/B (inlet closed, outlet open, pulsed)


def initial_state() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(controller vector, per-wheel array, HBA vector)."""
    wheels = np.zeros((4, WHEEL_STATE_SIZE))
    wheels[:, A_SINCE_HD_S] = 1e9
    wheels[:, A_ABS_QUIET_S] = 1e9
    wheels[:, A_VALVE_QUIET_S] = 1e9
    wheels[:, A_HOLD_PREV] = -1.0
    wheels[:, A_UNBRAKED_S] = 1e9
    ctl = np.zeros(CTL_SIZE)
    ctl[C_REF_EXCLUDED] = -1.0
    return ctl, wheels, hba.initial_state()


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _persisted(ctl, new_ex, dt, p):
    """A pending change of the excluded wheel (to ``new_ex``, -1 = none) one period older; True (and made) once it has
    persisted for ``reference_implausible_time_s``."""
    ctl[C_REF_PERSIST_S] += dt
    if ctl[C_REF_PERSIST_S] >= p.esp_reference_implausible_time_s - 1e-9:
        ctl[C_REF_EXCLUDED] = float(new_ex)
        ctl[C_REF_PERSIST_S] = 0.0
        return True
    return False


@nb.njit(cache=True, nogil=True, error_model="numpy")
def fastest_two(vw, ex):
    """Among the wheels other than ``ex``: the fastest one's index (-1: none), its speed and the second fastest
    speed (-1.0 where there is none)."""
    first = -1
    v1 = -1.0
    v2 = -1.0
    for i in range(4):
        if i == ex:
            continue
        if vw[i] > v1:
            v2 = v1
            v1 = vw[i]
            first = i
        elif vw[i] > v2:
            v2 = vw[i]
    return first, v1, v2


@nb.njit(cache=True, nogil=True, error_model="numpy")
def braking_outlier(vw, ex, abs_quiet_s, p, unbraked_s=None):
    """While braking: the wheel that may be implausibly fast (a blown or too-small tire), else -1. It is the fastest
    wheel other than the excluded ``ex``, alone: more than ``reference_implausible_frac`` above the SECOND fastest (a
    smaller rolling radius makes one wheel fast; a reference drifted low under a whole-car slip sees several wheels,
    or one wheel the ABS released, come back), and without valve activity for ``reference_braking_abs_quiet_time_s``
    (``abs_quiet_s``; None: all quiet): a wheel whose inlet was closed or outlet opened (its own ABS, the rear
    select-low, the GMA) is recovering toward the car's speed from below, never a fast tire's signature - unless
    (``reference_unbraked_outlier_flag``, ``unbraked_s`` = A_UNBRAKED_S) two other wheels have been unbraked for that
    time: a wheel without brake torque rolls at the car's speed, so a wheel faster than them by the band is above the
    car's speed whatever its valves do (K5, r41 #212: a rear blown at the pedal, its valves kept busy by the rear
    select-low, carried the reference 10.5 m/s over a car at 8 m/s; the ABS then dumped all four wheels to 1 bar)."""
    first, v1, v2 = fastest_two(vw, ex)
    if first < 0 or v1 <= v2 * (1.0 + p.esp_reference_implausible_frac):
        return -1
    if abs_quiet_s is not None and abs_quiet_s[first] < p.esp_reference_braking_abs_quiet_time_s - 1e-9:
        if unbraked_others(unbraked_s, first, ex, p) < 2:
            return -1
    return first


@nb.njit(cache=True, nogil=True, error_model="numpy")
def unbraked_others(unbraked_s, first, ex, p):
    """How many wheels other than ``first`` and ``ex`` have been unbraked (A_UNBRAKED_S) for at least
    ``reference_braking_abs_quiet_time_s`` (0 with ``reference_unbraked_outlier_flag`` = 0 or no ``unbraked_s``)."""
    n = 0
    if unbraked_s is None or p.esp_reference_unbraked_outlier_flag < 0.5:
        return 0
    for i in range(4):
        if i != first and i != ex and unbraked_s[i] >= p.esp_reference_braking_abs_quiet_time_s - 1e-9:
            n += 1
    return n


@nb.njit(cache=True, nogil=True, error_model="numpy")
def second_fastest(vw, ex):
    """The second fastest wheel speed among the wheels other than ``ex`` (-1: none left out), not below 0."""
    return max(fastest_two(vw, ex)[2], 0.0)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def braking_onset(ctl, p):
    """True within ``reference_braking_onset_s`` of the brake-light switch coming on (always with the seeded defect
    ``reference_braking_outlier_flag`` = 0): the 968b8ea braking test applies to every wheel there."""
    return p.esp_reference_braking_outlier_flag < 0.5 or ctl[C_BRAKED_S] < p.esp_reference_braking_onset_s - 1e-9


@nb.njit(cache=True, nogil=True, error_model="numpy")
def plausible_reference(ctl, vw, braking, p, dt, a_x=0.0, abs_quiet_s=None, valve_quiet_s=None, unbraked_s=None):
    """Wheel-signal plausibility of the reference speed (module doc, step 1): updates ``ctl[C_REF_EXCLUDED]`` and
    returns (max of the plausible wheels, True when the excluded wheel changed this period). ``a_x``: measured
    longitudinal acceleration; ``abs_quiet_s``: per wheel, time since its ABS mode was last other than OFF (None: all
    quiet); ``valve_quiet_s``: the same with its valve activity (A_VALVE_QUIET_S; None: all quiet) - all used only by
    the braking test (``reference_braking_plausibility_flag``)."""
    ex = int(ctl[C_REF_EXCLUDED])
    changed = False
    if p.esp_reference_braking_plausibility_flag > 0.5 and braking and ctl[C_STARTED] > 0.5:
        # while braking the car cannot speed up: the reference may rise at most at max(a_x, 0) + RISE_MARGIN (as
        # blowout_compensation.reference_step), and an ABS-recovering wheel comes back up to the vehicle speed from
        # below, never above it - a wheel faster than that bound by the band for the same time is implausible. Only
        # a wheel without ABS activity for reference_braking_abs_quiet_time_s is left out (a reference drifting low
        # in a long all-wheel slip must not make a recovering wheel look fast), and only above the ABS cut-off.
        hi = ctl[C_V_REF] + (max(a_x, 0.0) + bc.RISE_MARGIN_MPS2) * dt
        fast = -1
        best = 0.0
        if np.median(vw) > p.esp_abs_min_speed_mps and not braking_onset(ctl, p):
            # past the pedal onset only a lone, valve-quiet fast wheel (braking_outlier) is judged (ice, a_x
            # over-reading deceleration by 1.4 m/s^2: the reference drifted low, RL - released by the rear select-low,
            # own ABS mode off - was the wheel nearest the car's speed and was left out; the other three locked 0.49 s)
            cand = braking_outlier(vw, ex, valve_quiet_s, p, unbraked_s)
            if cand >= 0 and (vw[cand] > hi * (1.0 + p.esp_reference_implausible_frac)
                              or unbraked_others(unbraked_s, cand, ex, p) >= 2):
                # (reference_unbraked_outlier_flag) two unbraked wheels show the car's speed: a wheel above them by
                # the band is left out even when the reference already rides it (it cannot rise above itself)
                fast = cand
        elif np.median(vw) > p.esp_abs_min_speed_mps:
            # at the pedal onset (or always with reference_braking_outlier_flag = 0, the seeded defect: 968b8ea) any
            # wheel ABS left alone: the reference was set by free-rolling wheels just before, it cannot have drifted
            # low yet, but a tire blown within the unbraked persistence time may have lifted it and make the intact
            # wheels' ABS hold, closing the blown rear's inlet through the select-low (F4b)
            for i in range(4):
                quiet = abs_quiet_s is None or abs_quiet_s[i] >= p.esp_reference_braking_abs_quiet_time_s - 1e-9
                if i != ex and quiet and vw[i] > hi * (1.0 + p.esp_reference_implausible_frac) and vw[i] / hi > best:
                    best = vw[i] / hi
                    fast = i
        if fast >= 0:
            if _persisted(ctl, fast, dt, p):
                ex = fast
                changed = True
        else:
            ctl[C_REF_PERSIST_S] = 0.0
    elif p.esp_reference_plausibility_flag > 0.5 and not braking:
        # judged above the ABS cut-off only (slower, the sensors' edge-timing noise is a large fraction of the speed)
        fast = bc._candidate_ws(vw, 0.0, p.esp_reference_implausible_frac, -1) \
            if np.median(vw) > p.esp_abs_min_speed_mps else ex
        if fast != ex:
            if _persisted(ctl, fast, dt, p):
                ex = fast
                changed = True
        else:
            ctl[C_REF_PERSIST_S] = 0.0
    v_max = 0.0
    for i in range(4):
        if i != ex:
            v_max = max(v_max, vw[i])
    return v_max, changed


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _estimate(mode, p_est, p_src, dt, p, open_before_s=0.0, line=False):
    """The ECU's model of a wheel pressure (nominal unit data, spec 2 simplified model). ``open_before_s``: how
    long the inlet has already been open for a build (B/BP) before this period (accumulator dead time t0); ``line``:
    mode N through the line lag (the A_P_LINE estimate), else the source at once (A_P_EST)."""
    if mode == W_N:
        if line:
            # (A_P_LINE, pressure_estimate_line_flag >= 2) inlet open, circuit open to the master cylinder: the wheel
            # follows the source through the line, the unit's first-order lag tau_line (the same nominal model as the W_B
            # USV check-valve inflow and the H/BPM return flow below; plant/brakes/esp_unit.py row N), integrated exactly
            # over the period with p_src held: p_src + (p_est - p_src)*exp(-dt/tau_line). A_P_EST takes the source at
            # once (a dump one period after W_N stored 167.8 bar, the wheel held 53.6). Value 1 of the flag (A_P_EST
            # through the line lag too, I9's candidate) was deleted in session j (J2): 7 shipped traces changed, 26 of
            # the lead's h3 points worse by > 0.05 m (tire_blowout_findings.md I9)
            return p_src + (p_est - p_src) * math.exp(-dt / p.esp_unit_line_time_constant_s)
        return p_src
    if mode == W_B or mode == W_BP:
        rate = p.esp_unit_pump_build_rate_pa_per_s * (1.0 if mode == W_B else p.esp_unit_pulse_duty_frac)
        if p.esp_unit_pressure_source > 0.5:  # accumulator (EHB of paper 004): orifice-like fill
            # after the inlet's dead time t0 (tire_blowout.md 5 eq. 29; the unit passes nothing for t0 after the
            # inlet opens, plant sedan_esp.py), then the exponential fill p_acc - (p_acc - p)*exp(-t/tau) over the
            # part of this period past t0 (issue #10: without t0, and with one explicit Euler step per 5 ms period,
            # the estimate read 20 bar high during the first build and 62 vs 49 bar at its end - the compensating
            # wheel was under-built by ~22 % and the tire-capacity estimate biased high)
            fill_s = max(open_before_s + dt - max(open_before_s, p.esp_unit_inlet_dead_time_s), 0.0)
            tau = p.esp_unit_accumulator_time_constant_s / (1.0 if mode == W_B else p.esp_unit_pulse_duty_frac)
            acc = p.esp_unit_accumulator_pa
            built = acc - (acc - p_est) * math.exp(-fill_s / tau) if p_est < acc else p_est
            built = min(built, max(p.esp_unit_pump_relief_pa, p_est))
        else:
            built = min(p_est + rate * dt, max(p.esp_unit_pump_relief_pa, p_est))
        if mode == W_B:  # USV check valve: a higher driver pressure flows in through the line (tau_line), as the unit
            return max(built, p_est + (p_src - p_est) * min(dt / p.esp_unit_line_time_constant_s, 1.0))
        return built  # BP: the pulsed inlet is the bottleneck, no follow of the driver (plant/brakes/esp_unit.py)
    if (mode == W_H or mode == W_BPM) and p_est > p_src:  # USV open: the inlet's return check valve (plant esp_unit)
        return p_est + (p_src - p_est) * min(dt / p.esp_unit_line_time_constant_s, 1.0)
    if mode == W_BPM:
        return p_est + min(p.esp_unit_pulse_duty_frac * max(p_src - p_est, 0.0) * min(dt / p.esp_unit_line_time_constant_s, 1.0),
                           p.esp_unit_pulse_duty_frac * p.esp_unit_pump_build_rate_pa_per_s * dt)
    if mode == W_D:
        return p.esp_unit_lpa_pressure_pa + (p_est - p.esp_unit_lpa_pressure_pa) * math.exp(-dt / p.esp_unit_dump_time_constant_s)
    if mode == W_T:  # inlet closed: the wheel only falls toward the driver's pressure, never rises
        if p_est > p_src:
            return max(p_est - p.esp_unit_exit_rate_pa_per_s * dt, p_src)
        return p_est
    return p_est  # holds


@nb.njit(cache=True, nogil=True, error_model="numpy")
def abs_wheel_decel_mps2(bst, i, dt):
    """Wheel i's deceleration for the ABS rules (``esp.abs_signal_filter_flag``): minus the least-squares slope of
    its last ABS_DECEL_WINDOW_N wheel-speed samples (``blowout_compensation.wheel_accel_mps2``, the first-derivative
    Savitzky-Golay filter of degree 1, Savitzky and Golay 1964), read from the newest end of the wheel-speed window
    that blowout_compensation.reference_step writes every period for all four wheels whether or not that function is
    enabled; 0 before the window holds 2 samples."""
    return -bc.wheel_accel_mps2(bst, i, dt, ABS_DECEL_WINDOW_N)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def abs_hold_limit(wheels, i, new, slip, p, dt):
    """The ABS hold's time limit (``esp.abs_hold_limit_flag``): the mode of wheel i after ``new`` (abs_fn.abs_step's
    decision), and True when this rule turned a hold into a dump step.

    Bosch's ABS control cycle holds the pressure only while it waits for the wheel to re-accelerate; a wheel that
    does not re-accelerate under the held pressure is still heading for lock and the pressure is reduced again, in
    steps (Bosch Automotive Handbook, ABS control cycle, braking on a slippery road: hold for a time T1, then
    stepwise reduction while the +a signal does not come; workshop descriptions of the cycle: slip still increasing
    during the hold -> pressure reduction). abs.py's hold ends only at the dump slip L_DUMP or back at L_HOLD with
    the wheel turning with the car: a wheel held between them past the friction peak loses lateral force for as long
    as its slip creeps toward L_DUMP (RH2: 1.1 s at 12-18.5 % slip, 35.9 bar). Here, during a hold with the slip
    above L_HOLD, every ``abs_hold_window_s`` the window's mean slip is compared with the previous window's: risen
    by more than ``abs_hold_slip_rise_frac`` (the wheel slowing relative to the car: no re-acceleration) -> a dump
    step of one ESP period (the next period abs.py's slip_recovering makes it a hold again, the windows restart). A
    held wheel on the stable side of the mu-slip curve settles at a constant slip (constant pressure, brake torque
    balanced by a friction below the peak) and is left alone."""
    if new != abs_fn.HOLD or slip <= p.esp_abs_hold_slip_frac:
        wheels[i, A_HOLD_S] = 0.0
        wheels[i, A_HOLD_SUM] = 0.0
        wheels[i, A_HOLD_PREV] = -1.0
        return new, False
    wheels[i, A_HOLD_S] += dt
    wheels[i, A_HOLD_SUM] += slip * dt
    if wheels[i, A_HOLD_S] >= p.esp_abs_hold_window_s - 1e-9:
        mean = wheels[i, A_HOLD_SUM] / wheels[i, A_HOLD_S]
        prev = wheels[i, A_HOLD_PREV]
        wheels[i, A_HOLD_S] = 0.0
        wheels[i, A_HOLD_SUM] = 0.0
        wheels[i, A_HOLD_PREV] = mean
        if prev >= 0.0 and mean > prev + p.esp_abs_hold_slip_rise_frac:
            wheels[i, A_HOLD_PREV] = -1.0
            return abs_fn.DUMP, True
    return new, False


@nb.njit(cache=True, nogil=True, error_model="numpy")
def reference_update(ctl, vw_arr, v_plaus, ref_changed, bls, a_x, valve_quiet_s, p, dt, unbraked_s=None):
    """The reference speed of this period from the plausible wheels' max ``v_plaus`` (module doc, step 1): the fall
    bound (accelerometer + margin) always, the rise bounds while braking (``reference_braking_plausibility_flag``,
    ``reference_braking_rise_limit_flag``); ``ctl[C_V_REF]`` holds the previous value (not written here)."""
    decel = abs(min(a_x, 0.0)) + p.esp_reference_decel_margin_mps2
    if ref_changed:
        # the reference rode the implausible wheel: it restarts from the plausible ones (the accelerometer bound
        # would otherwise hold the inflated value for seconds)
        v_ref = v_plaus
    else:
        v_ref = max(v_plaus, ctl[C_V_REF] - decel * dt)
        if p.esp_reference_braking_plausibility_flag > 0.5 and bls:
            # braking: the car cannot speed up faster than the accelerometer says (+ margin, as the blowout
            # compensation's reference); 0 = seeded defect (F4b: the reference rides a wheel blown just before the pedal)
            v_cap = ctl[C_V_REF] + (max(a_x, 0.0) + bc.RISE_MARGIN_MPS2) * dt
            if not braking_onset(ctl, p):
                # past the pedal onset the bound holds back only a possible fast tire (braking_outlier) while its test
                # persists: the other wheels lift the reference freely (a wheel coming back from a release, or several
                # wheels together, show the car's speed: a reference drifted low must rise back to them)
                ex_now = int(ctl[C_REF_EXCLUDED])
                cand = braking_outlier(vw_arr, ex_now, valve_quiet_s, p, unbraked_s)
                if cand >= 0:
                    v_rest = 0.0
                    for i in range(4):
                        if i != ex_now and i != cand:
                            v_rest = max(v_rest, vw_arr[i])
                    v_ref = max(min(v_ref, v_cap), v_rest)
                elif p.esp_reference_braking_rise_limit_flag > 0.5:
                    # (reference_braking_rise_limit_flag) ABS practice: the reference's rise is limited to the car's
                    # largest possible acceleration (Kelsey-Hayes US 5,644,490; Bosch: the reference increase limited
                    # by the maximum possible vehicle acceleration) - a braked car's speed changes at the measured
                    # a_x, so ONE wheel lifts the reference at most at a_x + margin, whatever its valves do (a dumped
                    # flat front spins up to its smaller radius: G8, 25.2 -> 32.6 m/s in 0.3 s, the twin stopped
                    # braking; a wheel-speed sensor fault, a compact spare). Two wheels together still lift it freely
                    # (the second fastest): a reference drifted low comes back to them; one recovering wheel brings
                    # it back at the margin.
                    v_lim = ctl[C_V_REF] + (a_x + p.esp_reference_braking_rise_margin_mps2) * dt
                    v_ref = max(min(v_ref, v_lim), second_fastest(vw_arr, ex_now))
            else:
                v_ref = min(v_ref, v_cap)
    return v_ref


@nb.njit(cache=True, nogil=True)
def cap_hold_dump(wm, p_w, cap):
    """A wheel held at a pressure cap (ABS hold, circuit open) and dumped above it by more than 1 bar
    (bc.PRESSURE_MARGIN_PA); ABS's own dump/hold/isolated hold win. The blowout braking rule's rear cap and the
    blown-side front cap (blown_side_front_cap_flag) share it."""
    if wm == W_D or wm == W_H or wm == W_HI:
        return wm
    if p_w > cap + bc.PRESSURE_MARGIN_PA:
        return W_D
    if p_w >= cap:
        return W_H
    return wm


@nb.njit(cache=True, nogil=True, error_model="numpy")
def esp_step(ctl, wheels, hst, meas, p, dt, t, m_abs0, m_hba, events, n_events, abs_guards, hba_guards, bst, m_blow):
    """One ESP period; writes the wheel valve modes into ``wheels[:, A_WHEEL_MODE]``; returns n_events."""
    r_w = p.body_wheel_radius_m
    vw0 = meas.wheel_speed_fl_radps * r_w
    vw1 = meas.wheel_speed_fr_radps * r_w
    vw2 = meas.wheel_speed_rl_radps * r_w
    vw3 = meas.wheel_speed_rr_radps * r_w
    v_max = max(max(vw0, vw1), max(vw2, vw3))
    vw_arr = np.array([vw0, vw1, vw2, vw3])
    tpms = meas.tpms_alarm_wheel_index if meas.tpms_alarm_wheel_ok > 0.5 else 0.0
    # blowout compensation's reference from the wheels not known/suspected blown, rate-bounded (issue #10)
    v_ref_intact = bc.reference_step(bst, vw_arr, meas.longitudinal_accel_mps2, tpms, dt, p)
    blown = bc.excluded_wheel(bst)
    wheels_ok = (meas.wheel_speed_fl_ok > 0.5 and meas.wheel_speed_fr_ok > 0.5 and meas.wheel_speed_rl_ok > 0.5
                 and meas.wheel_speed_rr_ok > 0.5)
    if ctl[C_STARTED] < 0.5:
        ctl[C_V_REF] = v_max
        ctl[C_STARTED] = 1.0
        ctl[C_GMA_START] = -1e9
        ctl[C_GMA_WHEEL] = -1.0
        for i in range(4):
            wheels[i, A_VW_PREV] = v_max
        hst[hba.S_P_PREV] = meas.master_pressure_pa
    bls = meas.brake_light_switch_flag > 0.5
    ctl[C_BRAKED_S] = ctl[C_BRAKED_S] + dt if bls else 0.0
    v_plaus, ref_changed = plausible_reference(ctl, vw_arr, bls, p, dt, meas.longitudinal_accel_mps2,
                                               wheels[:, A_ABS_QUIET_S], wheels[:, A_VALVE_QUIET_S],
                                               wheels[:, A_UNBRAKED_S])
    v_ref = reference_update(ctl, vw_arr, v_plaus, ref_changed, bls, meas.longitudinal_accel_mps2,
                             wheels[:, A_VALVE_QUIET_S], p, dt, wheels[:, A_UNBRAKED_S])
    if blown >= 0:
        v_ref = v_ref_intact  # a blown wheel turns faster (smaller radius): the reference ignores it
    ctl[C_V_REF] = v_ref
    ctl[C_T] = t

    # pressure sensor: valid and plausible against the brake-light switch
    p_mc = meas.master_pressure_pa
    implausible = (bls and p_mc < p.esp_plausibility_pressure_pa) or (not bls and p_mc > 2.0 * p.esp_plausibility_pressure_pa)
    ctl[C_IMPLAUSIBLE_S] = ctl[C_IMPLAUSIBLE_S] + dt if implausible else 0.0
    if ctl[C_IMPLAUSIBLE_S] >= p.esp_plausibility_time_s or meas.master_pressure_ok < 0.5:
        ctl[C_SENSOR_LATCH] = 1.0
    sensor_ok = ctl[C_SENSOR_LATCH] < 0.5
    abs_ok = meas.esp_valves_ok > 0.5 and wheels_ok
    pump_ok = meas.return_pump_ok > 0.5
    ctl[C_SENSOR_OK] = 1.0 if sensor_ok else 0.0
    ctl[C_ABS_OK] = 1.0 if abs_ok else 0.0
    ctl[C_HBA_AVAILABLE] = 1.0 if (abs_ok and pump_ok and sensor_ok and p.brake_assist_enabled_flag > 0.5) else 0.0

    # ABS per wheel
    # ABS cut-off (spec 4.3: ABS disabled below 5 km/h of *vehicle* speed). The ECU only has v_ref, which while ABS
    # regulates can be low by the slip of the fastest wheel; a wheel beyond the dump slip L_DUMP is dumped, so
    # v_ref >= (1 - L_DUMP)*v. Releasing only once v_ref <= (1 - L_DUMP)*V_min guarantees v <= V_min when the
    # wheels go back to the driver (a release at v_ref = V_min locked wheels at up to 5.2 km/h: issue #9 review).
    v_cut = p.esp_abs_min_speed_mps * (1.0 - p.esp_abs_dump_slip_frac)
    abs_allowed = abs_ok and bls and v_ref > v_cut
    if not bls:
        bst[bc.S_PAIR_LOW] = 0.0  # the pair rule after a rear rejection lasts until the brake is released
    comp_wheel = int(bst[bc.S_TARGET]) if int(bst[bc.S_MODE]) != bc.IDLE else -1  # blowout compensation brakes it
    filt = p.esp_abs_signal_filter_flag > 0.5
    dump_new0 = False  # a front began an ABS dump in this period (gma_rejected_marker_dump_flag)
    dump_new1 = False
    for i in range(4):
        vw = vw0 if i == 0 else vw1 if i == 1 else vw2 if i == 2 else vw3
        slip = (v_ref - vw) / max(v_ref, 1.0)
        a_w = (wheels[i, A_VW_PREV] - vw) / dt
        if filt and int(wheels[i, A_MODE]) != abs_fn.DUMP:  # filtered wheel deceleration (ABS_DECEL_WINDOW_N)
            a_w = abs_wheel_decel_mps2(bst, i, dt)
        wheels[i, A_VW_PREV] = vw
        wheels[i, A_SLIP] = slip
        wheels[i, A_DECEL] = a_w
        mode = int(wheels[i, A_MODE])
        # ABS also guards the wheel the blowout compensation brakes without the driver (slip control, issue #10)
        # (engaged only once lock threatens: slip above the dump threshold; the Dugoff tire has no force peak,
        # so holding at the 10 % threshold would cut force the compensation needs)
        allowed_i = abs_allowed or (abs_ok and i == comp_wheel and v_ref > v_cut
                                    and (slip > p.esp_abs_dump_slip_frac or int(wheels[i, A_MODE]) != abs_fn.OFF))
        new, reason = abs_fn.abs_step(mode, wheels[i, A_BUILD_S], slip, a_w, allowed_i, p.esp_abs_dump_slip_frac,
                                      p.esp_abs_hold_slip_frac, p.esp_abs_dump_decel_mps2, p.esp_abs_rebuild_decel_mps2,
                                      p.esp_abs_idle_time_s,
                                      abs_fn.TABLE, abs_guards)
        # (blowout_compensation.rejected_hold_limit_flag, 0 = the code before) after a rejected FRONT detection, while
        # the driver steers a curve (the steered reference yaw rate beyond yaw_deadband_deg_per_s: the front axle must
        # carry the curve's lateral force; friction circle), the hold limit also on both fronts, not on the twin nor the
        # rears (tire_blowout_findings.md J6): the function's release/build and the rejection's re-apply step put both
        # fronts at their lock levels and an ABS hold has no time limit - the front axle then lost the curve's lateral
        # force (false FR alarm, 650 m curve). Measured, not shipped (session j, J6; values deleted): the rejected front
        # only, or either variant also on a straight road (straight false alarms worse, fa_c2026 #16 a new violation)
        rej_w = int(bst[bc.S_REJECTED])
        rej_hold = (p.blowout_compensation_rejected_hold_limit_flag > 0.5 and i < 2 and 0 <= rej_w < 2
                    and int(bst[bc.S_MODE]) == bc.REJECTED
                    and abs(bc.reference_yaw_rate(meas.steering_angle_rad, v_ref, p))
                    > p.blowout_compensation_yaw_deadband_radps)
        if p.esp_abs_hold_limit_flag > 0.5 or rej_hold:
            new, stepped = abs_hold_limit(wheels, i, new, slip, p, dt)
            if stepped:
                reason = abs_fn.G_LOCK  # a held wheel that does not re-accelerate is heading for lock (abs_hold_limit)
        elif p.blowout_compensation_rejected_hold_reset_flag > 0.5:
            # (rejected_hold_reset_flag, 0 = the code before = the window state frozen) the hold limit does not apply
            # to this wheel now (rej_hold's curve gate dropped, REJECTED ended): its window state is reset as at the
            # end of a hold, so a later gated-on hold starts two fresh windows (review RJ3: a stale partial window and
            # an old hold's mean let it dump after one window)
            wheels[i, A_HOLD_S] = 0.0
            wheels[i, A_HOLD_SUM] = 0.0
            wheels[i, A_HOLD_PREV] = -1.0
        if (new == abs_fn.DUMP and mode != abs_fn.DUMP and i == comp_wheel
                and p.blowout_compensation_braking_rule_flag > 0.5
                and (slip > p.esp_abs_hold_slip_frac or p.blowout_compensation_predump_slip_flag < 0.5)):
            # braking rule: the re-build after this dump goes back to here - only a dump with slip evidence marks the
            # lock level (predump_slip_flag: a noise-triggered deceleration dump at 2.8 % slip latched 31 of 64 bar)
            p_dump = wheels[i, A_P_LINE] if p.esp_pressure_estimate_line_flag > 1.5 else wheels[i, A_P_EST]
            bst[bc.S_P_PREDUMP] = p_dump
            bst[bc.S_AW_PREDUMP] = a_w  # the wheel's deceleration at that pressure (abs_dump_bound_flag)
            # ... and over the window before it, noise-robust (abs_dump_noise_flag; pressures of this period not pushed yet)
            bst[bc.S_P_DUMPWIN], bst[bc.S_AW_DUMPWIN] = bc.dump_window_reading(bst, i, p_dump, dt)
        elif (new == abs_fn.OFF and mode != abs_fn.OFF and i == comp_wheel
              and p.blowout_compensation_braking_rule_flag > 0.5):
            # ABS let the wheel go (build_idle: no hold/dump for abs_idle_time_s), so the dump's pressure is no lock
            # level any more (a noise-triggered dump during the build had capped the wheel there for the rest of the
            # stop: FL straight 114 km/h mu 0.5, 363 N, FR held at 15 bar at 2 % slip, 6.04 m vs none 5.73 m)
            bst[bc.S_P_PREDUMP] = -1.0
        if new != mode:
            if wheels[i, A_LOGGED] < ABS_LOG_CAP:
                n_events = log_event(events, n_events, t, m_abs0 + i, mode, new, reason)
                wheels[i, A_LOGGED] += 1.0
            wheels[i, A_BUILD_S] = 0.0
        elif new == abs_fn.BUILD:
            wheels[i, A_BUILD_S] += dt
        if i < 2 and new == abs_fn.DUMP and mode != abs_fn.DUMP:
            # the front's lock level (gma_rejected_split_flag); -1: this dump ends the rejected front's re-apply step
            # (esp.lock_level_line_flag, 0 = the code before = A_P_EST) read on the line-lag estimate, the pressure the
            # wheel locked at (plant esp_unit row N: the wheel follows the source through tau_line; A_P_EST jumps to it)
            p_lk = wheels[i, A_P_LINE] if p.esp_lock_level_line_flag > 0.5 else wheels[i, A_P_EST]
            ctl[C_LOCK_P0 + i] = p_lk if ctl[C_LOCK_P0 + i] >= 0.0 else 0.0
            if i == 0:
                dump_new0 = True
            else:
                dump_new1 = True
        wheels[i, A_MODE] = new
        if new == abs_fn.HOLD or new == abs_fn.DUMP:
            wheels[i, A_SINCE_HD_S] = 0.0
        else:
            wheels[i, A_SINCE_HD_S] += dt
        if (i < 2 and p.blowout_compensation_gma_rejected_split_quiet_flag > 0.5 and ctl[C_LOCK_P0 + i] > 0.0
                and wheels[i, A_SINCE_HD_S] >= ABS_ACTIVE_WINDOW_S):
            # (gma_rejected_split_quiet_flag, 0 = the code before = kept until the pedal is released) a front's lock
            # level is forgotten once ABS is quiet on it (no hold or dump for 0.3 s: ABS no longer active, spec 4.3) -
            # the rule braking_lock_floor already uses: a level found on one surface says nothing once the wheel runs
            # below its limit, possibly on another surface (review RI4: a stale split reading starts a GMA the car
            # without the function would not). The rejected front's skip marker (-1) is not a level and stays.
            ctl[C_LOCK_P0 + i] = 0.0
        wheels[i, A_ABS_QUIET_S] = wheels[i, A_ABS_QUIET_S] + dt if new == abs_fn.OFF else 0.0
        wheels[i, A_REQUEST] = new  # ABS modes are requests 0..3

    # select-low on the rear axle: both rear wheels follow the more critical request
    m2 = int(wheels[2, A_MODE])
    m3 = int(wheels[3, A_MODE])
    rear = m2 if PRIORITY[m2] >= PRIORITY[m3] else m3
    wheels[2, A_REQUEST] = rear
    wheels[3, A_REQUEST] = rear

    # yaw-moment build-up delay (GMA): ABS active on one front wheel only (not the blowout compensation's wheel)
    m_b = int(bst[bc.S_MODE])
    tgt = int(bst[bc.S_TARGET]) if (m_b == bc.BUILD or m_b == bc.HOLD or m_b == bc.LIMITED) else -1
    if 0 <= tgt < 2:
        if ctl[C_GMA_BLOCK] < 0.5 and int(ctl[C_GMA_WHEEL]) == 1 - tgt:
            ctl[C_GMA_WHEEL] = -1.0  # a GMA the compensation's wheel started is not a split-mu GMA
        if int(ctl[C_GMA_WHEEL]) == tgt and bst[bc.S_LIMIT_CODE] == bc.LIMIT_SPIN_FRONT:
            # the spin-front wheel (blowout_compensation spin_front_flag) is the car's yaw-stability brake, not the
            # high-mu side of a split-mu stop: the GMA's delay of it is ended
            ctl[C_GMA_WHEEL] = -1.0
        if (p.blowout_compensation_gma_blown_front_flag > 0.5 and int(ctl[C_GMA_WHEEL]) == tgt
                and 0 <= blown < 2 and blown != tgt):
            # (gma_blown_front_flag) a GMA on the compensating front started by the blown front's activity: ended
            ctl[C_GMA_WHEEL] = -1.0
            if ctl[C_GMA_BLOCK] < 0.5:
                ctl[C_GMA_PRE] = tgt + 1.0  # it ran before the function acted (gma_rejected_pre_flag)
        ctl[C_GMA_BLOCK] = tgt + 1.0
    elif ctl[C_GMA_BLOCK] > 0.5 and int(wheels[int(ctl[C_GMA_BLOCK]) - 1, A_MODE]) == abs_fn.OFF:
        ctl[C_GMA_BLOCK] = 0.0
    if ctl[C_GMA_BLOCK] < 0.5 or not bls:
        ctl[C_GMA_PRE] = 0.0
    if not bls:
        ctl[C_LOCK_P0] = 0.0
        ctl[C_LOCK_P1] = 0.0
        ctl[C_LOCK_REJ] = 0.0
    blk = int(ctl[C_GMA_BLOCK]) - 1
    # (gma_blown_front_flag) the blown front released by a compensation on the other front: its ABS hold/dump activity
    # is the flat tire's / the release's, not a split-mu road's - it does not start the GMA on the compensating wheel
    # (the GMA held that wheel at ~10 bar against the braking rule's 65 bar, tire_blowout_findings.md Q4)
    blk_b = blown if (0 <= tgt < 2 and 0 <= blown < 2 and blown != tgt
                      and p.blowout_compensation_gma_blown_front_flag > 0.5) else -1
    # (gma_rejected_flag) after a FRONT detection is rejected, while the block of its compensating front is kept: the
    # rejected front - released by the function, then given the driver's pressure at once (reject_reapply_flag) - is
    # in ABS because of the function's own release/re-apply, not a split-mu road: its activity does not start the GMA
    # on the compensating front either (false FR alarm in a 650 m left curve, braking: the GMA took FL 29.9 -> 15.8 bar
    # on the curve's own yaw and held it for ~1 s against FR at 45.7 bar - 2.13 m vs 0.35 m without the function)
    rej = int(bst[bc.S_REJECTED])
    blk_r = rej if (tgt < 0 and 0 <= blk < 2 and 0 <= rej < 2 and rej != blk
                    and p.blowout_compensation_gma_rejected_flag > 0.5) else -1
    if blk_r >= 0 and p.blowout_compensation_gma_rejected_pre_flag > 0.5 and int(ctl[C_GMA_PRE]) - 1 == blk:
        # (gma_rejected_pre_flag, 0 = seeded defect = ignored always) the rejected front's one-sided activity had
        # started the GMA on the compensating front BEFORE the detection (gma_blown_front_flag ended it): split-mu
        # evidence the function did not cause - once the detection is rejected it counts again, so the GMA restarts
        # (false FR alarm on split-mu, FR on snow, 80 km/h pedal 0.3: FL at 47 bar without it, 3.50 m vs 1.89 none)
        blk_r = -1
    blk_a = blk  # the compensating front's activity masked by its block
    if blk_r >= 0 and p.blowout_compensation_gma_rejected_split_flag > 0.5:
        # (gma_rejected_split_flag, 0 = seeded defect = both fronts masked until the block ends) after the rejection the
        # function no longer acts: the GMA is judged from the two fronts' ABS lock levels, as the no-function ESP would
        # meet them. Under one driver's pressure the front whose lock level is at most half the other's reaches ABS
        # alone - a split surface (UN R13-H Annex 6 split-mu test: k_H / k_L >= 2; a locking front's pressure is
        # proportional to its friction) - so its activity counts and the other's stays masked: the GMA starts on the
        # high-mu front. Lock levels within a factor 2 (a curve or an even road, H2's case) keep both masked as before.
        # RI1: FR on snow named before an HBA pedal, FL built and rejected; FL at its dry lock level never left ABS,
        # both masked, no GMA: FL 41-47 vs FR 8-11 bar, 14.635 m vs 1.888 without the function.
        # The rejected front's lock level counts only from its second dump after the rejection: it was released, then
        # re-applied at once to the driver's pressure (reject_reapply_flag), so its first dump marks that step, not the
        # road (the estimate jumps to the source: RI1's case read FR 150 bar against FL 58, the wrong way round)
        if int(ctl[C_LOCK_REJ]) - 1 != blk_r:
            ctl[C_LOCK_REJ] = blk_r + 1.0
            # (gma_rejected_marker_dump_flag, 0 = the code before = -1 always) the marker is set after this period's
            # ABS loop: if the rejected front began its dump in this period, that dump is the re-apply step's and
            # the marker is consumed (0: the next dump, the first road lock, stores its level) - review RJ3
            began = dump_new0 if blk_r == 0 else dump_new1
            ctl[C_LOCK_P0 + blk_r] = (0.0 if (began and p.blowout_compensation_gma_rejected_marker_dump_flag > 0.5)
                                      else -1.0)
        p_r = ctl[C_LOCK_P0 + blk_r]
        p_k = ctl[C_LOCK_P0 + blk]
        if p_r > 0.0 and p_k > 0.0:
            if 2.0 * p_r <= p_k:
                blk_r = -1  # the rejected front is the low-mu side: its activity counts
            elif 2.0 * p_k <= p_r:
                blk_a = -1  # the compensating front is the low-mu side: its activity counts
    # A FRONT wheel only NAMED by the TPMS (excluded from the reference, not yet detected: the compensation IDLE, not
    # after a rejection) has a rolling radius the ECU does not know (spec tire_blowout.md 6: R_out -> R_in): its
    # nominal-radius speed overstates its periphery, the slip ABS reads on it is short by (R_out - R_eff)/R_eff
    # (a flat FR at 22-32 % true slip read 0-3 %, tire_blowout_findings.md H6 43 #30) - a wheel-speed signal known bad.
    named_f = blown if (0 <= blown < 2 and int(bst[bc.S_BLOWN]) < 0 and int(bst[bc.S_MODE]) == bc.IDLE) else -1
    # (named_front_gma_flag) its ABS activity is no evidence of a split-mu road: it does not start the GMA on the other
    # front (as a known-blown front's does not: gma_blown_front_flag; ABS practice: a wheel whose speed signal is
    # implausible is no basis for the control of the others). 43 #30: the flat FR's ABS started the GMA on FL, held at
    # 23 bar against the driver's 150 bar while the flat's drag turned the car toward FR. The other (intact) front's
    # activity still counts: the GMA it starts lands on the named front - the wheel whose lock level ABS cannot find is
    # treated as the side with the larger brake force, its build delayed and its yaw moment limited (measured: masking
    # both fronts while one is named - no GMA at all - moved 15 points worse, a new violation r41 #469; findings I4)
    blk_n = named_f if p.esp_named_front_gma_flag > 0.5 else -1
    act0 = wheels[0, A_SINCE_HD_S] < ABS_ACTIVE_WINDOW_S and blk_a != 0 and blk_b != 0 and blk_r != 0 and blk_n != 0
    act1 = wheels[1, A_SINCE_HD_S] < ABS_ACTIVE_WINDOW_S and blk_a != 1 and blk_b != 1 and blk_r != 1 and blk_n != 1
    spin_front = tgt if (0 <= tgt < 2 and bst[bc.S_LIMIT_CODE] == bc.LIMIT_SPIN_FRONT) else -1
    if act0 != act1 and ctl[C_GMA_WHEEL] < 0.0 and abs_allowed and (1 if act0 else 0) != spin_front:
        # (never on the spin-front wheel: ended above, it was re-armed here in the same period, its start reset
        # every period, while the other front's ABS was active - the stability brake pulsed for the whole spin)
        ctl[C_GMA_START] = t
        ctl[C_GMA_WHEEL] = 1.0 if act0 else 0.0  # the other (high-mu) front wheel is delayed
    if not abs_allowed:
        ctl[C_GMA_WHEEL] = -1.0
    g = int(ctl[C_GMA_WHEEL])
    # the GMA's yaw limitation judges the RAW measured yaw rate (a curve's own yaw counts too: status h item 4; the
    # candidate judging the deviation from the steered reference, H7, was deleted in session j - it added never-worse
    # violations on the tire-blowout envelope, tire_blowout_findings.md H7 / J3)
    yaw_dev = meas.yaw_rate_radps
    if (g >= 0 and int(wheels[g, A_MODE]) == abs_fn.HOLD and 0 <= rej < 2
            and p.blowout_compensation_gma_rejected_hold_dump_flag > 0.5
            and yaw_dev * (1.0 if g == 0 else -1.0) > p.esp_yaw_dump_rate_radps):
        # (gma_rejected_hold_dump_flag, 0 = seeded defect = the yaw limitation waits for the wheel's ABS hold to end)
        # after a FRONT rejection the GMA's (high-mu) wheel was built by the function and the driver before any GMA
        # could delay it, and ABS may hold it at its high-mu lock level indefinitely: the yaw limitation's dump toward
        # its side (yaw beyond yaw_dump_rate) outranks the hold - a hold only stops the rise, the yaw says the brake-force
        # difference is already too large (PRIORITY: DUMP over HOLD). I12: FR on snow named, 100 km/h, pedal 0.3: FL
        # held at 48 bar from 0.9 s with the GMA started at 1.1 s, 15.898 m vs 2.633 m without the function.
        wheels[g, A_REQUEST] = R_DUMP
    if g >= 0 and (int(wheels[g, A_MODE]) == abs_fn.OFF or int(wheels[g, A_MODE]) == abs_fn.BUILD):
        elapsed = t - ctl[C_GMA_START]
        # yaw toward the high-mu side (braking the left wheel yaws the car left, CCW +)
        toward = yaw_dev * (1.0 if g == 0 else -1.0)
        if toward > p.esp_yaw_dump_rate_radps:
            wheels[g, A_REQUEST] = R_DUMP
        elif toward > p.esp_yaw_hold_rate_radps:
            wheels[g, A_REQUEST] = R_GMA_HOLD
        elif (p.esp_gma_pressure_order_flag > 0.5 and blown >= 2 and g == 3 - blown
              and wheels[g, A_P_EST] < wheels[1 - g, A_P_EST] - RAMP_SETTLED_PA
              and (p.esp_gma_pressure_order_flag < 1.5
                   or (meas.inlet_valve_rl_ok if blown == 2 else meas.inlet_valve_rr_ok) < 0.5
                   or (p.esp_gma_pressure_order_flag > 2.5 and int(wheels[1 - g, A_MODE]) == abs_fn.OFF
                       and wheels[1 - g, A_P_EST] >= p_mc - RAMP_SETTLED_PA))):
            # (value 3, N6: value 2 OR the other front - the one whose ABS started the GMA - has left ABS (its ABS mode
            # OFF: the pulsed re-build ended) at the driver's pressure (estimate within RAMP_SETTLED_PA of p_mc; the
            # estimate alone runs ahead of a pulsed re-build - rb13 #114: FR 19.5 bar true, estimate >= 23.5, at
            # 1.53 s): that front carries the full driver's
            # pressure without a lock below it, so the ESP's own numbers no longer show it as the low-mu side and the
            # GMA's premise (delay the high-mu front while the other is held at its lower lock level) is gone. rb5
            # #72: FR's one-period noise dump, re-built to the driver's 46 bar by 1.45 s, FL held at 20-23 bar to
            # 2.2 s. While the ABS front is still below the driver's pressure (re-building to its lock level, as at
            # rb13 #114 - FR 8-24 bar under p_mc 24.5 with FL held at 10.9 bar in BOTH cars) the GMA stays as before)
            # (value 2, M6: only while the blown rear's OWN inlet is diagnosed stuck closed - that rear is unbraked in
            # the car without the function too, so the fronts are the only brakes the two cars can differ on; value 1
            # everywhere added a new violation where the OTHER rear was stuck, t_r41 #51, L7)
            # (gma_pressure_order_flag, 0 = the code before) the GMA delays the presumed HIGH-mu front relative to the
            # one in ABS: it limits the DIFFERENCE of the fronts' pressures (see gma_follow_flag). Once the ABS front is
            # re-built above the delayed wheel, holding that wheel makes the difference point the other way - a yaw
            # moment toward the ABS side the GMA was meant to limit. Below the other front (and without yaw toward its
            # own side) the delayed wheel re-builds in pulses from the master like any ABS re-build (L7: rb5 #72, a
            # noise dump of FR at the pedal onset held FL at 20-23 bar for 1 s against FR re-built to 46 bar).
            # Only with a REAR known blown or TPMS-named (blown >= 2; the ESP without the function never has one, so
            # the no-function car is the code before): both fronts are intact, so their pressure order is their brake
            # force order. Not with a front blown or named (its flat tire's force is not its pressure's) nor without
            # a named wheel: applied there too, rb5 #33's twin (FL flat, unknown) rebuilt the flat FL the GMA held
            # at 1-8 bar and went 0.843 -> 1.665 m. Only for the front OPPOSITE the blown rear (g == 3 - blown): paper
            # 004's counter-moment brakes the side away from the blown wheel (eq. 28), so a GMA hold of that front
            # below the blown side's front takes counter-moment away; a hold of the blown side's front below the
            # other adds counter-moment and stays as before (applied there too, rb13 #76 - RR, 115 km/h, fixed
            # steering - lost FR's hold at 10 bar against FL's 20-30: +2.931 -> -0.129 m, a new violation).
            wheels[g, A_REQUEST] = R_BUILD
        elif elapsed < p.esp_gma_duration_s and int(wheels[g, A_MODE]) == abs_fn.OFF:
            phase = elapsed - p.esp_gma_cycle_s * math.floor(elapsed / p.esp_gma_cycle_s)
            wheels[g, A_REQUEST] = R_GMA_PULSE if phase < p.esp_gma_pulse_s - 1e-9 else R_GMA_HOLD
        elif int(wheels[g, A_MODE]) == abs_fn.OFF:
            # after the delay (or a yaw hold) the held wheel re-builds in pulses like any ABS re-build, never by a
            # step to the driver's pressure: a 36 -> 179 bar step stopped the high-mu wheel within two controller
            # periods at 10 km/h (split-mu, 300 N: wheel at 0 rad/s with the car above 5 km/h, criterion 5)
            wheels[g, A_REQUEST] = R_GMA_PULSE

    # HBA
    hba_mode = hba.INACTIVE
    if p.brake_assist_enabled_flag > 0.5:
        ramp_done = True
        for i in range(4):
            src = p_mc if i < 2 else _prop(p_mc, p)
            if wheels[i, A_P_EST] - src >= RAMP_SETTLED_PA:  # a wheel still above the driver's pressure
                ramp_done = False
        old = int(hst[hba.S_MODE])
        new, reason = hba.hba_step(hst, p_mc, v_ref, bls, sensor_ok, abs_ok and pump_ok, ramp_done, dt, p, hba_guards)
        if new != old:
            n_events = log_event(events, n_events, t, m_hba, old, new, reason)
        hba_mode = new

    # blowout compensation (functions/blowout_compensation.py)
    inlet_ok = np.array([meas.inlet_valve_fl_ok, meas.inlet_valve_fr_ok, meas.inlet_valve_rl_ok, meas.inlet_valve_rr_ok])
    blow_req = np.zeros(4, dtype=np.int64)
    p_est = wheels[:, A_P_EST].copy()
    for i in range(4):  # ABS active per wheel (spec 4.3) for the blowout compensation (blown_front_hold_flag)
        bst[bc.S_ABS_ACTIVE + i] = 1.0 if wheels[i, A_SINCE_HD_S] < ABS_ACTIVE_WINDOW_S else 0.0
        bst[bc.S_P_LINE + i] = wheels[i, A_P_LINE]  # (lock_level_line_flag: braking_lock_floor's estimate)
    n_events = bc.blowout_step(bst, vw_arr, v_ref_intact, 1.0 if bls else 0.0, meas.longitudinal_accel_mps2,
                               meas.yaw_rate_radps, meas.steering_angle_rad, tpms, inlet_ok, p_est, p, dt, t, m_blow,
                               events, n_events, blow_req, meas.lateral_accel_mps2, p_mc)

    # arbitration and the ECU's pressure estimate
    # Per circuit, during an assist, which pressure source serves it is decided once by the front wheel (latched):
    # SRC_PUMP when the pump has lifted it more than 1 bar above the driver; SRC_DRIVER when ABS finds its lock
    # limit (slip beyond the hold threshold with a hold or dump) while the driver's pressure is more than 1 bar above
    # the wheel's - the driver alone reaches the ABS level. A SRC_DRIVER circuit (one switching valve, so its rear
    # wheel too) uses row A_DRIVER: plain ABS on the driver's pressure, as without HBA.
    for i in range(2):
        c = CIRCUIT[i]
        if hba_mode == hba.INACTIVE:
            ctl[C_PUMPED_C1 + c] = 0.0
        if hba_mode != hba.ACTIVE:
            ctl[C_SOURCE_C1 + c] = SRC_UNDECIDED
        elif ctl[C_SOURCE_C1 + c] == SRC_UNDECIDED:
            last = int(wheels[i, A_WHEEL_MODE])
            lifted = last == W_B or last == W_BP or p.esp_hba_rampout_pumped_only_flag < 0.5 or blown >= 0
            # (the pump lifted it: above the driver in a pump build mode; a wheel left above an easing driver's
            # pressure, or the GMA's wheel held at the driver's, is not pump-served - latching it made the
            # circuit's rear pumped on split-mu with an easing driver: CMA-ES/random seed 7 counterexamples)
            if wheels[i, A_P_EST] - p_mc > RAMP_SETTLED_PA and lifted:
                ctl[C_SOURCE_C1 + c] = SRC_PUMP
                ctl[C_PUMPED_C1 + c] = 1.0
            elif (p_mc - wheels[i, A_P_EST] > RAMP_SETTLED_PA and wheels[i, A_SLIP] > p.esp_abs_hold_slip_frac
                  and (int(wheels[i, A_MODE]) == abs_fn.HOLD or int(wheels[i, A_MODE]) == abs_fn.DUMP)):
                ctl[C_SOURCE_C1 + c] = SRC_DRIVER
    # The yaw-moment limitation governs the assist too (issue #9, split-mu): once the GMA is engaged its (high-mu)
    # front wheel keeps the driver's pressure source (row A_DRIVER: GMA pulses from the master cylinder, capped at
    # p_mc, holds with the circuit open, so a wheel the pump lifted before drains back to p_mc through the inlet's
    # check valve). The pump lifting it past the GMA (86 vs 60 bar at 80 km/h) raised the yaw moment the driver has
    # to hold: 2.04 vs 1.56 m lane offset, 7.8 vs 4.9 deg heading, 229 vs 55 deg steering (hba_split_mu_80kph).
    # Not while a wheel is known or suspected blown (blown >= 0): then the one-sided ABS activity is the blown
    # wheel's release, not a split-mu road, and the blowout arbitration (issue #10) governs as before.
    gma_wheel = int(ctl[C_GMA_WHEEL])
    # (gma_rear_named_flag, 0 = the code before = any known or suspected blown wheel) that premise holds for a blown
    # FRONT only: the GMA judges the FRONT axle's one-sided ABS activity (the rears are select-low), so a blown or
    # TPMS-named REAR releases no front and the fronts' split-mu evidence stands. 1 (shipped): the GMA follow applies as
    # without the function - the GMA limits the DIFFERENCE of the fronts' pressures, so once the pump lifted the other
    # front above the driver's the GMA's wheel is pumped up to it - while the wheel otherwise keeps the row the code
    # before gave it. With a REAR named the GMA's wheel stayed in the HBA row, where its one-period pump pulses
    # (gma_pulse_s 5 ms) are shorter than the accumulator inlet's dead time t0 (15 ms, spec tire_blowout.md 7): nothing
    # flowed, the GMA's 'pulse build' was a 1-s hold - bb29 #69 (RR, straight, 79 km/h, mu .44, HBA) FL 27.4 bar for
    # 1.0 s against the twin's 28 -> 47 bar, 1.389 m vs 1.210 m (1: 0.878 m). (J4 also measured gma_hba_flag's
    # driver's-source cap for a named rear - #69 0.887 m, but random 31 #9 (RL, oversteering, panic pedal) +6.256 ->
    # -0.719 m: the capped outer FR rebuilt from the master, the car spun - and did not ship it; removed by RJ1, findings
    # J4 / RJ1)
    follow_blown = -1 if (blown >= 2 and p.esp_gma_rear_named_flag > 0.5) else blown
    # a wheel only NAMED by the TPMS: excluded from the reference but not (yet) detected by the compensation
    tpms_only = blown >= 0 and int(bst[bc.S_BLOWN]) < 0
    comp_now = int(bst[bc.S_TARGET]) if int(bst[bc.S_MODE]) != bc.IDLE else -1  # the compensation's wheel now
    for i in range(4):
        row = hba_mode
        src_i = p_mc if i < 2 else _prop(p_mc, p)
        if hba_mode == hba.TERMINATING and (wheels[i, A_P_EST] - src_i < RAMP_SETTLED_PA or (
                ctl[C_PUMPED_C1 + CIRCUIT[i]] < 0.5 and blown < 0 and p.esp_hba_rampout_pumped_only_flag > 0.5)):
            # ramp-out (P8) only hands back pressure the pump built: a wheel of a circuit the pump never served is
            # above the driver's pressure only because the driver eased off, and drains back through the inlet's
            # check valve as without HBA (the 200 bar/s ramp-out there made the assisted stop differ from the
            # no-HBA one and cost 0.047 m over 181 m: CMA-ES seed 2026, split-mu, easing driver)
            row = T_DONE
        elif hba_mode == hba.ACTIVE and (ctl[C_SOURCE_C1 + CIRCUIT[i]] == SRC_DRIVER or (
                i >= 2 and ctl[C_SOURCE_C1 + CIRCUIT[i]] == SRC_UNDECIDED) or (
                i == gma_wheel and (blown < 0 or (tpms_only and blown < 2 and p.esp_gma_hba_named_front_flag > 0.5))
                and p.esp_gma_hba_flag > 0.5)):
            # (gma_hba_named_front_flag, session o O2; 0 = the code before = any known or suspected blown wheel ends it)
            # also while a FRONT is only NAMED by the TPMS (excluded from the reference, the compensation not yet
            # acting): the GMA's wheel keeps the driver's row - held with the circuit open and built in the GMA's
            # pulses from the master cylinder, as without the function. In the HBA row its hold is isolated (HI) and
            # its one-period pump pulses are shorter than the accumulator inlet's dead time (J4's finding for a named
            # rear): the naming froze it (fb5 / rb5 #1: FR at 45.1 bar to 1.7 s against the twin's 47.4)
            # a rear wheel is pumped above its proportioned driver pressure only once the pump has had to lift its
            # circuit's front wheel (pumping it while the front still rebuilt below the driver put the rear into ABS
            # cycling the car without HBA does not have)
            row = A_DRIVER
        req = int(wheels[i, A_REQUEST])
        if ((row == A_DRIVER or (row == hba.ACTIVE and follow_blown != blown)) and i == gma_wheel and follow_blown < 0
                and p.esp_gma_follow_flag > 0.5
                and ctl[C_SOURCE_C1 + CIRCUIT[i]] != SRC_DRIVER and ctl[C_SOURCE_C1 + CIRCUIT[1 - i]] == SRC_PUMP
                and max(wheels[1 - i, A_P_EST], wheels[i, A_P_EST]) > p_mc + RAMP_SETTLED_PA):
            # GMA follow: the pump lifted the other (presumed low-mu) front above the driver's pressure; the driver's
            # pressure cap would hold the GMA's wheel below the other side for the whole stop. The GMA limits the
            # high-mu wheel's pressure relative to the low-mu wheel's: it is pumped up to the other front's pressure
            # (not past it) and held there; the yaw limitation (hold/dump) and its own ABS still govern it.
            # Only once the pump served the other circuit (SRC_PUMP): an easing driver leaves the other front above
            # p_mc too (following it there made HBA 1.20 m longer than none, test_hba_gma_and_rebuild easing point).
            # Paper stop, 0.1 rad/s wheel-speed noise, seeds 1-10: 7 did not stop in 12 s (38-54 deg) -> 49.1-55.1 m.
            row = hba.ACTIVE
            toward = yaw_dev * (1.0 if i == 0 else -1.0)
            if wheels[i, A_P_EST] < wheels[1 - i, A_P_EST] - RAMP_SETTLED_PA:
                if (req == R_GMA_PULSE or req == R_GMA_HOLD) and toward <= p.esp_yaw_hold_rate_radps:
                    req = R_OFF  # (ACTIVE row: pump build)
            elif (req == R_OFF or req == R_BUILD or req == R_GMA_PULSE) and not (
                    i == comp_now and follow_blown != blown and p.esp_gma_follow_comp_flag > 0.5):
                # (gma_follow_comp_flag, 0 = the code before) not on the blowout compensation's front (a rear blowout
                # with its opposite rear's inlet stuck: LIMITED on the same-side front, _substitute): its pressure
                # above the other front's IS the compensation's counter-moment (paper 004 eq. 28, added on top of the
                # target's pressure), which the follow's 'not past the other front' cancelled - J8: the lead's bb29
                # #75 (RR named) with RL's inlet stuck, FL held at or below FR (FL - FR mean -4.3 bar over the first
                # LIMITED second): 3.165 m; without the cap -0.2 bar, 2.725 m (twin 4.773). The pump-up to the other
                # front stays (as without the function, and in the compensation's direction: removing the follow
                # from that wheel entirely froze FL at the GMA's pulses, #69 with RL stuck 1.397 -> 1.678 m)
                req = R_GMA_HOLD  # at the other front's pressure: hold, circuit isolated
        wm = ARBITRATION[row, req] if abs_ok else W_N
        if (i >= 2 and row == hba.ACTIVE and (wm == W_B or wm == W_BP)
                and p.esp_hba_rear_select_low_flag > 0.5
                and wheels[i, A_P_EST] >= wheels[5 - i, A_P_EST] + RAMP_SETTLED_PA
                and ((blown < 0 and ctl[C_SOURCE_C1 + CIRCUIT[5 - i]] == SRC_PUMP)
                     or (tpms_only and p.esp_hba_rear_select_low_tpms_flag > 0.5))):
            # rear select-low on pressure during the pump build: the X-split pumps a rear with its circuit's front, so
            # on split-mu the high-mu rear of the low-mu front's circuit was pumped above the other rear (86-89 vs
            # 65-75 bar at 80 km/h dry/wet) - a yaw moment no ABS rear has (its rears follow the more critical one);
            # a rear builds only up to the other rear's pressure (estimate), then holds with the circuit isolated.
            # (hba_rear_select_low_tpms_flag) While a wheel is only NAMED by the TPMS (excluded from the reference,
            # the blowout compensation not yet acting: no rear cap of its own) the select-low holds whatever the other
            # rear's source: the named wheel's circuit is not pump-served, so its rear stays on the driver's
            # proportioned pressure while the pump lifts the other circuit's rear - random 29 #46, FL named: RL
            # pumped to 78-83 bar against RR's 31-36, the car yawed toward FL and spun (8.64 m vs 2.01 m without
            # compensation; with the rule 0.60 m). Once the wheel is DETECTED the compensation's braking rule
            # (S_REAR_CAP) governs the rear pair, as before.
            wm = W_HI
        if (wm == W_BP and row == hba.ACTIVE and i < 2 and ctl[C_SOURCE_C1 + CIRCUIT[i]] == SRC_UNDECIDED
                and p_mc - wheels[i, A_P_EST] > RAMP_SETTLED_PA and hst[hba.S_RATE] >= 0.0 and blown < 0
                and p.esp_hba_master_rebuild_flag > 0.5):
            # Source still undecided and the driver's pressure above the wheel: the ABS re-build comes from the master
            # cylinder (BPM, slowing as it nears p_mc) as without HBA; the pump takes over only at the driver's
            # pressure. The pump's constant duty*G_pump re-build here shifted the ABS cycling and made HBA 0.11-0.15 m
            # longer than no HBA (CMA-ES, 128.6 km/h wet, mu 0.763, 1769 kg, 98 N at 17 /s; driver 58.7 bar just
            # above the lock pressure). Not while the driver's pressure falls (dp_mc/dt < 0): an easing driver
            # (UN R139 category B: eased to 0.6 F_ABS) is the assist's case - the pump keeps re-building toward
            # the ABS level the driver's pressure is leaving (BPM there cost 0.015 m of the R139 stop).
            wm = W_BPM
        brake_rule = p.blowout_compensation_braking_rule_flag > 0.5
        if (abs_ok and brake_rule and bst[bc.S_P_BRAKE] >= 0.0 and i == int(bst[bc.S_TARGET])
                and (blow_req[i] == bc.Q_BUILD or blow_req[i] == bc.Q_HOLD)):
            # blowout braking rule (blowout_compensation.braking_rule): the compensating front wheel while the driver
            # brakes goes to S_P_BRAKE, after an ABS dump to no more than its pressure at the dump's start, by the
            # accumulator's pulsed build, then holds (circuit isolated); an ABS dump always wins, an ABS hold stops the
            # build but not the way down to the target
            if wm != W_D:
                p_t = bst[bc.S_P_BRAKE]
                if bst[bc.S_P_PREDUMP] > 0.0:
                    p_t = min(p_t, bst[bc.S_P_PREDUMP])
                # (pressure_estimate_line_flag = 3, candidate, review RI4; not shipped, J2) the wheel is compared with the ceiling on the
                # estimate the ceiling was stored from (A_P_LINE at flag >= 2): at 2 a level stored from the line estimate
                # is compared with A_P_EST, which jumped to the source in N (61.9 vs 167.8 bar after I9's step), so this
                # 'down to the target' dump ran until A_P_EST read the 62 bar with the line estimate near 21 bar (I9's
                # 20 -> 167.8 bar step, nominal dump model); lead's bb47 #5 robustness 2: 3.593 m, 3: 4.128 m (= flag 0)
                p_c = wheels[i, A_P_LINE] if (p.esp_pressure_estimate_line_flag > 2.5 and bst[bc.S_P_PREDUMP] > 0.0
                                              and p_t >= bst[bc.S_P_PREDUMP]) else wheels[i, A_P_EST]
                if (p.esp_lock_level_line_flag > 0.5 and bst[bc.S_LOCK_P] > 0.0 and abs(
                        p_t - p.blowout_compensation_braking_lock_floor_frac * bst[bc.S_LOCK_P]) < 1.0):
                    # (lock_level_line_flag) the target is braking_lock_floor's floor, a fraction of a level stored on
                    # the line estimate: the wheel is compared with it on that estimate too
                    p_c = wheels[i, A_P_LINE]
                if p_c > p_t + 1.0e5 and wheels[i, A_P_EST] > bst[bc.S_P_REQ] + 1.0e5:
                    wm = W_D  # down to the target (also against an ABS hold: less pressure is always allowed)
                elif wm == W_H:
                    pass  # ABS hold: no build
                elif p_c < p_t - 1.0e5:
                    wm = W_BP
                else:
                    wm = W_HI
            if wm == W_H and wheels[i, A_P_EST] > src_i + RAMP_SETTLED_PA:
                wm = W_HI  # (as below: with the USV open the return check valve would drain it)
            if wm == W_D and wheels[i, A_P_EST] < p.esp_unit_lpa_pressure_pa + 0.5e5:
                wm = W_HI  # already empty: keep the inlet closed
        elif abs_ok and brake_rule and i >= 2 and bst[bc.S_REAR_CAP] >= 0.0 and blow_req[i] == bc.Q_NONE:
            # blowout braking rule: the rear pair held at its cap (ABS hold, circuit open), dumped above it by more
            # than 1 bar; ABS's own hold/dump win
            wm = cap_hold_dump(wm, wheels[i, A_P_EST], bst[bc.S_REAR_CAP])
        elif (abs_ok and brake_rule and p.blowout_compensation_blown_side_front_cap_flag > 0.5 and bls and i < 2
              and int(bst[bc.S_BLOWN]) >= 2 and i == int(bst[bc.S_BLOWN]) - 2 and blow_req[i] == bc.Q_NONE
              and (int(bst[bc.S_MODE]) == bc.BUILD or int(bst[bc.S_MODE]) == bc.HOLD)
              and (p.blowout_compensation_blown_side_front_cap_flag < 1.5 or bc.toward_blown_side(
                  int(bst[bc.S_BLOWN]), meas.yaw_rate_radps - bc.reference_yaw_rate(meas.steering_angle_rad, v_ref, p))
                  > p.blowout_compensation_yaw_deadband_radps)):
            # (blowout_compensation.blown_side_front_cap_flag, session o O2) a detected REAR blowout while the driver
            # brakes: the blown side's FRONT is held at no more than the other front's pressure (ABS hold, circuit open),
            # dumped above it by more than 1 bar; ABS's own hold/dump win. Paper 004 eqs. 26-28 balance the blown rear's
            # drag with the opposite rear on top of the driver's pressure p_0, on the premise that the other wheels brake
            # alike; a blown-side front braked above the other front adds a moment toward the blown side the balance does
            # not contain (the front-axle select-low of the ESP's yaw-moment limitation, Bosch Automotive Handbook ABS)
            # Value 2: only while the yaw error (measured yaw rate - the steered reference, the compensation's own yaw
            # judgement) points toward the blown side beyond yaw_deadband (1 deg/s; the braking rule's gate): value 1
            # ungated over-compensated a follower on a straight road (r23 #23, the car yawed away and spun, findings O2)
            # Value 3: value 2 with the hold at 1 bar ABOVE the other front (dump above it + 1 bar more): at 2 the hold
            # began at equality, so at a pedal onset with both fronts building from the master together the blown
            # side's front was held at the first period's level (0.1 bar; rb13 #39, the GMA then kept it at 9.8 bar
            # against FR's 19-23) - equal fronts add no moment, the select-low has nothing to limit there
            cap = wheels[1 - i, A_P_EST]
            if p.blowout_compensation_blown_side_front_cap_flag > 2.5:
                cap = cap + bc.PRESSURE_MARGIN_PA
            wm = cap_hold_dump(wm, wheels[i, A_P_EST], cap)
        elif abs_ok and blow_req[i] != bc.Q_NONE:
            wm = BLOWOUT_ARBITRATION[blow_req[i], wm]
            if blow_req[i] == bc.Q_HOLD and wm == W_HI and src_i > wheels[i, A_P_EST] + 1.0e5:
                wm = W_N  # the driver asks for more than the compensation holds: the driver's pressure
            if wm == W_D and wheels[i, A_P_EST] < p.esp_unit_lpa_pressure_pa + 0.5e5:
                wm = W_HI  # released wheel already empty: keep the inlet closed
            if (blow_req[i] == bc.Q_BUILD or blow_req[i] == bc.Q_HOLD) and (wm == W_BPM or wm == W_HI):
                # after an ABS dump the compensating wheel re-builds from the accumulator (not from the empty
                # master cylinder) up to the required pressure, then holds
                wm = W_BP if wheels[i, A_P_EST] < bst[bc.S_P_REQ] - 1.0e5 else W_HI
            if (wm == W_H or wm == W_BPM) and wheels[i, A_P_EST] > src_i + RAMP_SETTLED_PA:
                # a compensating wheel above the driver's pressure: with the USV open (H, BPM) the inlet's return
                # check valve would drain it into the master cylinder (plant/brakes/esp_unit.py), so hold it with
                # the circuit isolated (HI) - what H/BPM did before the check valve was modelled (issue #9 review)
                wm = W_HI
        if abs_ok and int(bst[bc.S_REAPPLY]) == i and blow_req[i] == bc.Q_NONE:
            # blowout compensation rejected its detection while the driver brakes (reject_reapply_flag): the wheel it had
            # released gets the driver's pressure at once (inlet open, W_N) until the line model of its pressure
            # (tau_line from the pressure at the rejection, the ECU's W_N estimate jumps to the source at once) reaches
            # the pressure the other wheel of its axle carries (the driver's, as ABS lets it through), as without the
            # function; then (or at an ABS dump of it) ABS as usual
            if bst[bc.S_REAPPLY_P] < 0.0:
                bst[bc.S_REAPPLY_P] = wheels[i, A_P_EST]
            p_to = min(wheels[bc.OPPOSITE[i], A_P_EST], src_i)
            if wm == W_D or bst[bc.S_REAPPLY_P] >= p_to - 1.0e5:
                bst[bc.S_REAPPLY] = -1.0
            else:
                wm = W_N
                bst[bc.S_REAPPLY_P] += (src_i - bst[bc.S_REAPPLY_P]) * min(dt / p.esp_unit_line_time_constant_s, 1.0)
        if (abs_ok and i >= 2 and bst[bc.S_PAIR_LOW] > 0.5 and int(bst[bc.S_REAPPLY]) < 0
                and wheels[i, A_P_EST] > wheels[5 - i, A_P_EST] + 1.0e5):
            # rear rejected while braking (reject_pair_low_flag), its re-apply over: select-low on the pair's pressure -
            # the higher rear down to the lower one's (both rears carry the lower wheel's pressure: no rear yaw moment)
            wm = W_D
        wheels[i, A_WHEEL_MODE] = wm
        # valve activity (inlet closed, outlet open, pulsed re-build) ends the wheel's valve-quiet time whatever its
        # own ABS mode: a rear released by the select-low, or the GMA's wheel, recovers from below (braking_outlier)
        quiet_v = (wm == W_N or wm == W_B or not abs_ok) and int(wheels[i, A_MODE]) == abs_fn.OFF
        wheels[i, A_VALVE_QUIET_S] = wheels[i, A_VALVE_QUIET_S] + dt if quiet_v else 0.0
        wheels[i, A_P_LINE] = _estimate(wm, wheels[i, A_P_LINE], src_i, dt, p, wheels[i, A_INLET_OPEN_S], True)
        wheels[i, A_P_EST] = _estimate(wm, wheels[i, A_P_EST], src_i, dt, p, wheels[i, A_INLET_OPEN_S])
        if i >= 2 and bst[bc.S_PAIR_LOW] > 0.5 and int(bst[bc.S_REAPPLY]) == i and wm == W_N:
            # (reject_pair_low_flag) the re-applied rear's estimate is the re-apply's line model, not the source W_N's
            # estimate jumps to: ABS may dump the pair before the line has filled it (35 bar of 81, 120 km/h 500 N)
            wheels[i, A_P_EST] = bst[bc.S_REAPPLY_P]
        wheels[i, A_INLET_OPEN_S] = wheels[i, A_INLET_OPEN_S] + dt if (wm == W_B or wm == W_BP) else 0.0
        unbraked = max(wheels[i, A_P_EST], wheels[i, A_P_LINE]) < p.esp_plausibility_pressure_pa
        wheels[i, A_UNBRAKED_S] = wheels[i, A_UNBRAKED_S] + dt if unbraked else 0.0
    return n_events


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _prop(p_mc, p):
    """Rear pressure the proportioning valve passes for the master pressure p_mc (the valve's nominal curve)."""
    return proportioned_pa(p_mc, p.master_cylinder_proportioning_knee_pa, p.master_cylinder_proportioning_slope_frac)
