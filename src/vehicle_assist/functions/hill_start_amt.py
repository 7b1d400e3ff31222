"""Hill-start assist for a heavy AMT truck with an electro-pneumatic spring park brake (paper 000:
Wang, Zhao, Liu 2009; specification hill_start_amt.md sections 4 and 6).

The assist coordinates the park brake (through the 3/2 solenoid valve in its control line), the clutch
and the engine so that the truck neither rolls back nor stalls, with little clutch wear:

* **Entry (P11).** When the driver releases the service brake while the park brake is applied (park
  lamp on) and the truck stands in gear, the hill-start program starts and energises the 3/2 valve: the
  park brake stays applied whatever the driver does with the hand valve. Otherwise the AMT's normal
  start program runs.
* **Clutch (P10, P14).** Approach to the kiss point at v_A; then slip engagement whose rate follows
  the engine-speed drop rate (filtered dn_e/dt) and the input-shaft speed rate (filtered dn_in/dt, P10's
  second variable): fast drop -> slow engagement (heavy load / deep clutch), slow or no drop -> fast
  engagement, input shaft accelerating well with the engine not falling fast -> fast, input shaft not
  following while the engine falls -> slow, engine below the guard speed -> back off (anti-stall); when the
  slip speed is small and the truck moves, fast final lock-up at v_C.
* **No back-off below the holding torque.** Once the release is commanded and until the truck moves,
  the anti-stall back-off stops at the clutch position that carries the holding torque estimated from
  the measured grade and load (added by us: at 6.5 bar the slow release made the engine dip into the
  guard, and backing off past the holding torque rolled the empty truck back 0.24-1.1 m).
* **Small reverse growth (P6).** While the truck stands on the releasing park brake, the clutch engages
  no deeper than ``phase3_torque_frac`` x the estimated holding torque (the park force then grows only a
  little in reverse); the limit is lifted as soon as the truck moves either way or the park lamp goes
  out (the park brake has let go: the holding-torque estimate was too low). Without it the law
  kept engaging to twice the holding torque, the truck leapt when the brake let go, the engine was
  pulled into the guard and the back-off rolled the empty truck back 1.1 m at 6.5 bar.
* **Release instant (P6, P12, P14).** The valve is de-energised (chambers start to fill, if the driver
  has released the hand valve) when the clutch reaches the preset position x_rel of the start gear
  (paper-literal), or, load-adaptive, when the clutch capacity reaches k_rel times the torque that
  holds the truck, estimated from the measured grade (accelerometer at rest) and the measured load.
  The chambers need ~0.5 s before the force falls, so the release begins in phase 3 (F_t > F_i).
* **Stand-down.** A fault makes the assist stand down and say why (the guard name is the reason).
  What it then does is chosen so that the assist never makes the truck roll back:

  | reason | action |
  |---|---|
  | park switch failed, reservoir below 6.5 bar, engine speed lost - at entry | passive: the AMT's normal start program runs, as without the assist |
  | valve not holding (lamp goes out while energised: the driver's hand valve is releasing the brake) | drive on: keep the slip-engagement law running, so drive force builds as fast as the engine allows |
  | engine speed lost before the release command | hold: valve stays energised (park brake applied), clutch opens |
  | engine speed lost after the release command (the park force may already be falling) | drive on, at the slow engagement rate (no engine-speed feedback) |
  | park brake not released (stuck valve, slow chamber fill: lamp still on after the timeout, truck standing) | hold: 3/2 valve energised again (the spring brake re-applies), the clutch keeps resisting until the brake has been back on for the refusal delay, then opens |
  | grade beyond the engine torque: even at full pedal (HOLD), or at the driver's pedal for 1 s at the release point (ENGAGE_HELD), the engine's best governed torque above the launch speed is below margin x the estimated holding torque | hold: the park brake stays applied, clutch open (if the park brake's rated force is below the measured grade force m g sin(alpha): resist, the clutch carries margin x the rest); the driver must choose a lower gear, press further and retry, or give up |
  | grade beyond the park brake / adhesion: the truck slides back on the applied park brake (HOLD, APPROACH, ENGAGE_HELD), or rolls back after the release although the clutch delivered more than the estimated resistance (driven tandem at its adhesion limit) | catch, then hold |
  | rollback caught (after the release the truck moved backwards, or the engine was pulled below the guard after DONE) | catch: 3/2 valve energised (spring brake re-applies), clutch held while the engine runs above the guard; hold once the truck stands |

  It stays stood down until the driver takes over (service brake pressed or hand valve to park), or
  until a drive-on closes the clutch.

Changes of issue 7 (each can be switched off by a seeded-defect flag of the vehicle file, for the
verification engine; the shipped value 1 is the safe one):

* ``lockup_engine_check_flag``: (a) the slip engagement never asks more clutch torque than the engine's
  best governed torque at the driver's pedal above the launch speed (``T_cap <= k_ceil*T_best(theta)``,
  ``T_best = max_{w in [w_launch, w_set]} min(K_gov (w_set - w), T_full(w))``), so the engine is never dragged
  below the launch speed; (b) the refusal compares the estimated holding torque with that available torque
  (not with the peak torque); (c) lock-up (``slip_small``) needs the engine at or above the launch speed with
  ``min(T_full(n_e), K_gov (w_set - w_launch)) >= k_lock*T_hold``; (d) LOCKUP synchronises with the clutch
  capacity following the engine torque, ``T_cap = T_e(n_e, theta) + max(J_e |slip|/t_sync, dT_min)``, and clamps
  only once the slip is below ``sync_slip``: no flywheel dump, no torque spike.
* ``rollback_catch_flag``: after the release (ENGAGE_RELEASING, LOCKUP, DONE) a truck moving backwards
  faster than ``rollback_catch_speed`` (or, after DONE, an engine pulled below the guard on the grade) is caught:
  CATCH energises the 3/2 valve, so the spring chambers exhaust and the spring applies the brake, and holds the
  clutch while the engine runs above the guard.

The controller sees measurements only (``m``); ``c`` is its state, ``p`` the vehicle record.
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import StateMachine, Transition, log_event, next_mode
from vehicle_assist.core.tables import interp
from vehicle_assist.functions.amt_launch import (
    engine_available_torque_nm,
    engine_best_torque_nm,
    full_load_torque_nm,
    governed_speed_radps,
    governor_gain_nm_per_radps,
)
from vehicle_assist.plant.powertrain.clutch import clutch_capacity_nm, clutch_position_for_capacity

MACHINE = StateMachine(
    "hill_start_amt",
    modes=("STANDBY", "NORMAL_START", "HOLD", "APPROACH", "ENGAGE_HELD", "ENGAGE_RELEASING", "LOCKUP",
           "DONE", "STOOD_DOWN", "CATCH"),
    transitions=(
        # entry (P11) and its preconditions
        Transition("STANDBY", "STOOD_DOWN", "park_switch_failed_at_entry"),
        Transition("STANDBY", "STOOD_DOWN", "reservoir_pressure_low_at_entry"),
        Transition("STANDBY", "STOOD_DOWN", "engine_speed_lost_at_entry"),
        Transition("STANDBY", "HOLD", "service_brake_released_on_park_brake"),
        Transition("STANDBY", "NORMAL_START", "service_brake_released_without_park_brake"),
        Transition("NORMAL_START", "STANDBY", "stopped_on_service_brake"),
        # faults and refusals during the start
        Transition("HOLD", "STOOD_DOWN", "valve_not_holding"),
        Transition("APPROACH", "STOOD_DOWN", "valve_not_holding"),
        Transition("ENGAGE_HELD", "STOOD_DOWN", "valve_not_holding"),
        # the truck slides back on the applied park brake (park-brake capacity or adhesion): resist with the clutch
        Transition("HOLD", "CATCH", "rollback_detected"),
        Transition("APPROACH", "CATCH", "rollback_detected"),
        Transition("ENGAGE_HELD", "CATCH", "rollback_detected"),
        Transition("HOLD", "STOOD_DOWN", "grade_beyond_engine_torque"),
        Transition("HOLD", "STOOD_DOWN", "engine_speed_lost"),
        Transition("APPROACH", "STOOD_DOWN", "engine_speed_lost"),
        Transition("ENGAGE_HELD", "STOOD_DOWN", "engine_speed_lost"),
        Transition("ENGAGE_HELD", "STOOD_DOWN", "grade_beyond_engine_torque"),
        Transition("ENGAGE_RELEASING", "STOOD_DOWN", "engine_speed_lost"),
        Transition("ENGAGE_RELEASING", "STOOD_DOWN", "park_brake_not_released"),
        Transition("ENGAGE_RELEASING", "STOOD_DOWN", "grade_beyond_adhesion"),
        # the driver takes over
        Transition("HOLD", "STANDBY", "driver_brakes"),
        Transition("APPROACH", "STANDBY", "driver_brakes"),
        Transition("ENGAGE_HELD", "STANDBY", "driver_brakes"),
        # the start (P10, P14)
        Transition("HOLD", "APPROACH", "accelerator_pressed"),
        Transition("APPROACH", "ENGAGE_HELD", "kiss_point_reached"),
        Transition("ENGAGE_HELD", "ENGAGE_RELEASING", "release_point_reached"),
        # fail-safe after the release: a truck moving backwards is caught (spring brake re-applied)
        Transition("ENGAGE_RELEASING", "CATCH", "rollback_detected"),
        Transition("LOCKUP", "CATCH", "rollback_detected"),
        Transition("DONE", "CATCH", "rollback_detected"),
        Transition("DONE", "CATCH", "engine_pulled_down_on_grade"),
        Transition("ENGAGE_RELEASING", "LOCKUP", "slip_small"),
        Transition("LOCKUP", "DONE", "clutch_closed"),
        Transition("DONE", "STANDBY", "stopped_on_service_brake"),
        Transition("CATCH", "STOOD_DOWN", "valve_not_holding"),
        Transition("CATCH", "STOOD_DOWN", "grade_beyond_park_brake"),
        Transition("CATCH", "STOOD_DOWN", "grade_beyond_adhesion"),
        Transition("CATCH", "STOOD_DOWN", "rollback_caught"),
        Transition("STOOD_DOWN", "DONE", "clutch_closed"),
        Transition("STOOD_DOWN", "STANDBY", "driver_takes_over"),
        Transition("CATCH", "STANDBY", "driver_takes_over"),
    ),
    doc=__doc__ or "",
)
TABLE = MACHINE.table()
(STANDBY, NORMAL_START, HOLD, APPROACH, ENGAGE_HELD, ENGAGE_RELEASING, LOCKUP, DONE, STOOD_DOWN, CATCH) = range(10)
GUARDS = MACHINE.guards
N_GUARDS = len(GUARDS)
G_SWITCH_FAILED = MACHINE.guard("park_switch_failed_at_entry")
G_RESERVOIR_LOW = MACHINE.guard("reservoir_pressure_low_at_entry")
G_ENGINE_LOST_ENTRY = MACHINE.guard("engine_speed_lost_at_entry")
G_ENTRY = MACHINE.guard("service_brake_released_on_park_brake")
G_NORMAL = MACHINE.guard("service_brake_released_without_park_brake")
G_STOPPED = MACHINE.guard("stopped_on_service_brake")
G_ROLLBACK = MACHINE.guard("rollback_detected")
G_TOO_STEEP = MACHINE.guard("grade_beyond_engine_torque")
G_VALVE_NOT_HOLDING = MACHINE.guard("valve_not_holding")
G_ENGINE_LOST = MACHINE.guard("engine_speed_lost")
G_NOT_RELEASED = MACHINE.guard("park_brake_not_released")
G_DRIVER_BRAKES = MACHINE.guard("driver_brakes")
G_ACCELERATOR = MACHINE.guard("accelerator_pressed")
G_KISS = MACHINE.guard("kiss_point_reached")
G_RELEASE = MACHINE.guard("release_point_reached")
G_PULLED_DOWN = MACHINE.guard("engine_pulled_down_on_grade")
G_SLIP_SMALL = MACHINE.guard("slip_small")
G_CLOSED = MACHINE.guard("clutch_closed")
G_BEYOND_PARK = MACHINE.guard("grade_beyond_park_brake")
G_BEYOND_ADHESION = MACHINE.guard("grade_beyond_adhesion")
G_CAUGHT = MACHINE.guard("rollback_caught")
G_TAKES_OVER = MACHINE.guard("driver_takes_over")
# refusals (contract of issue 7): code k >= 1 is REFUSAL_REASONS[k - 1]; the guard name is the reason
REFUSAL_REASONS = ("grade_beyond_engine_torque", "grade_beyond_adhesion", "grade_beyond_park_brake", "rollback_caught")
REFUSAL_GUARDS = np.array([MACHINE.guard(r) for r in REFUSAL_REASONS], dtype=np.int64)
ACTIVE = (HOLD, APPROACH, ENGAGE_HELD, ENGAGE_RELEASING, LOCKUP, CATCH)  # the assist drives the clutch
RELEASE_PRESET, RELEASE_LOAD_ADAPTIVE = 0, 1
RELEASE_MODES = {"preset_position": RELEASE_PRESET, "load_adaptive": RELEASE_LOAD_ADAPTIVE}

STATE_DTYPE = np.dtype([
    ("mode", "f8"),
    ("clutch_command_frac", "f8"),
    ("valve_command_flag", "f8"),            # 1 = 3/2 valve energised (park brake held)
    ("brake_was_applied_flag", "f8"),        # for the service-brake release edge
    ("engine_speed_prev_radps", "f8"),
    ("engine_speed_rate_radps2", "f8"),      # filtered dn_e/dt
    ("input_speed_prev_radps", "f8"),
    ("input_speed_rate_radps2", "f8"),       # filtered dn_in/dt (P10's second control variable)
    ("grade_estimate_rad", "f8"),            # from the accelerometer while standing
    ("hold_torque_estimate_nm", "f8"),       # clutch torque that holds the truck (load-adaptive release)
    ("release_commanded_flag", "f8"),
    ("mode_time_s", "f8"),                   # time in the current mode
    ("stand_down_action", "f8"),             # STAND_DOWN_PASSIVE / _HOLD / _DRIVE_ON
    ("hand_valve_was_released_flag", "f8"),  # for the 'hand valve moved to park' edge
    ("torque_short_time_s", "f8"),           # time at the release point with too little engine torque
    ("refusal_code", "f8"),                  # 0, or k: REFUSAL_REASONS[k - 1]
    ("standing_time_s", "f8"),               # time the truck has stood still without interruption
    ("spin_time_s", "f8"),                   # park brake released, clutch above the need, truck standing
    ("guards", "f8", (N_GUARDS,)),           # guard values of the tick (scratch: no allocation per tick)
])
STAND_DOWN_PASSIVE, STAND_DOWN_HOLD, STAND_DOWN_DRIVE_ON, STAND_DOWN_RESIST = range(4)


def initial_state() -> np.recarray:
    s = np.zeros(1, dtype=STATE_DTYPE).view(np.recarray)
    s.mode[0] = STANDBY
    return s


@nb.njit(cache=True, nogil=True, error_model="numpy")
def hold_torque_estimate_nm(mass_kg, grade_rad, rolling_coeff, wheel_radius_m, total_ratio, efficiency):
    """T_hold = m*g*(sin(alpha) + f*cos(alpha))*r_w/(i_g*i_0*eta): clutch torque that holds the truck.

    hill_start_amt.md 6.2 writes it without eta; with eta it is the torque the clutch must really carry
    (the driveline loses 12 % on the way to the wheels)."""
    if total_ratio <= 0.0:
        return np.inf
    return (mass_kg * 9.81 * (math.sin(grade_rad) + rolling_coeff * math.cos(grade_rad)) * wheel_radius_m
            / (total_ratio * efficiency))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def engagement_rate_per_s(p, engine_speed_radps, engine_speed_rate_radps2, input_speed_rate_radps2=np.nan):
    """Slip-engagement law of hill_start_amt.md 6.3 (phase B) with both control variables of paper 000 P10:
    the engine-speed change rate and the gearbox input-shaft speed change rate (NaN: not measured).

    * engine below the guard speed -> back off (anti-stall, first);
    * input shaft accelerating well (>= input_accel_fast) and the engine not falling fast -> v_fast (light
      load: the truck follows the clutch);
    * input shaft not accelerating (< input_accel_slow: standing or hardly following) while the engine falls
      (<= -dn_slow) -> v_slow (heavy load, or the clutch drags against the park brake);
    * otherwise the engine-speed law of 6.3 (v_slow / v_mid / v_fast by the engine-speed drop).
    """
    if engine_speed_radps < p.hill_start_assist_guard_speed_radps:
        return -p.hill_start_assist_back_off_rate_per_s  # anti-stall
    if not math.isnan(input_speed_rate_radps2):
        if (input_speed_rate_radps2 >= p.hill_start_assist_input_accel_fast_radps2
                and engine_speed_rate_radps2 > -p.hill_start_assist_speed_drop_fast_radps2):
            return p.hill_start_assist_engage_rate_fast_per_s  # P10: the vehicle follows, load light
        if (input_speed_rate_radps2 < p.hill_start_assist_input_accel_slow_radps2
                and engine_speed_rate_radps2 <= -p.hill_start_assist_speed_drop_slow_radps2):
            return p.hill_start_assist_engage_rate_slow_per_s  # P10: engine falls, input shaft does not follow
    if engine_speed_rate_radps2 <= -p.hill_start_assist_speed_drop_fast_radps2:
        return p.hill_start_assist_engage_rate_slow_per_s  # engine pulled down fast: heavy load or deep clutch
    if engine_speed_rate_radps2 <= -p.hill_start_assist_speed_drop_slow_radps2:
        return p.hill_start_assist_engage_rate_mid_per_s
    return p.hill_start_assist_engage_rate_fast_per_s  # engine not falling: light load, shallow clutch


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _position(p, torque_nm):
    return clutch_position_for_capacity(torque_nm, p.clutch_max_torque_nm, p.clutch_kiss_point_frac,
                                        p.clutch_capacity_exponent)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _resist(p, c, x, m, engine_ok, park_applied, x_ceiling, dt, x_support):
    """Clutch while catching a rollback: engage (its forward torque works against the rollback, up to what the
    engine carries above the launch speed) while the engine runs above the guard; below it back off. Once the
    truck has stood on the re-applied spring brake (lamp on) for the refusal delay, open: the brake holds.
    ``x_support`` > 0 (the park brake's rated force is below the measured grade force, issue 7): engage at v_A up to
    that position (the clutch carries the part of the grade the brake cannot) and never open below it."""
    if not engine_ok or m.engine_speed_radps < p.hill_start_assist_guard_speed_radps:
        return x - p.hill_start_assist_back_off_rate_per_s * dt
    if m.vehicle_speed_mps < 0.0:
        return min(max(x + p.hill_start_assist_approach_rate_per_s * dt, p.clutch_kiss_point_frac),
                   max(x_ceiling, x))
    if x_support > 0.0:
        target = min(x_support, max(x_ceiling, p.clutch_kiss_point_frac))
        if x < target:
            return min(max(x + p.hill_start_assist_approach_rate_per_s * dt, p.clutch_kiss_point_frac), target)
        return x
    if (park_applied and c.standing_time_s >= p.hill_start_assist_refusal_delay_s
            and c.mode_time_s >= p.hill_start_assist_refusal_delay_s):  # the re-applied brake had time to exhaust
        return x - p.hill_start_assist_back_off_rate_per_s * dt
    return x


@nb.njit(cache=True, nogil=True, error_model="numpy")
def step(c, m, p, dt, t, machine_id, events, n_events):
    """One controller period. Returns the updated event count."""
    gear = int(round(m.gear_engaged_index))
    ratio = 0.0
    if 1 <= gear <= len(p.gearbox_ratios):
        ratio = p.gearbox_ratios[gear - 1] * p.gearbox_final_drive_ratio
    standing = abs(m.vehicle_speed_mps) < p.hill_start_assist_standstill_speed_mps
    brake_applied = m.brake_pedal_frac >= p.hill_start_assist_brake_applied_frac
    brake_released_edge = c.brake_was_applied_flag > 0.5 and not brake_applied
    park_applied = m.park_lamp_flag > 0.5
    engine_ok = m.engine_speed_ok > 0.5
    check = p.hill_start_assist_lockup_engine_check_flag > 0.5
    catch_on = p.hill_start_assist_rollback_catch_flag > 0.5
    w_launch = p.hill_start_assist_launch_speed_min_radps

    # filtered engine-speed and input-shaft-speed rates (first-order low-pass of the finite differences)
    alpha = dt / (p.hill_start_assist_speed_rate_filter_s + dt)
    if engine_ok:
        raw = (m.engine_speed_radps - c.engine_speed_prev_radps) / dt if c.engine_speed_prev_radps > 0.0 else 0.0
        c.engine_speed_rate_radps2 += alpha * (raw - c.engine_speed_rate_radps2)
        c.engine_speed_prev_radps = m.engine_speed_radps
    if m.input_shaft_speed_ok > 0.5:
        raw = (m.input_shaft_speed_radps - c.input_speed_prev_radps) / dt
        c.input_speed_rate_radps2 += alpha * (raw - c.input_speed_rate_radps2)
        c.input_speed_prev_radps = m.input_shaft_speed_radps
    # grade from the accelerometer while the truck stands (reads g*sin(alpha) at rest)
    c.standing_time_s = c.standing_time_s + dt if standing else 0.0
    if standing and c.standing_time_s >= p.hill_start_assist_grade_settle_s and m.longitudinal_accel_ok > 0.5:
        c.grade_estimate_rad = math.asin(min(max(m.longitudinal_accel_mps2 / 9.81, -1.0), 1.0))
    c.hold_torque_estimate_nm = hold_torque_estimate_nm(m.vehicle_mass_kg, c.grade_estimate_rad,
                                                        p.body_rolling_resistance_coeff, p.body_wheel_radius_m, ratio,
                                                        p.gearbox_efficiency_frac)
    t_hold = c.hold_torque_estimate_nm

    cap = clutch_capacity_nm(c.clutch_command_frac, p.clutch_max_torque_nm, p.clutch_kiss_point_frac,
                             p.clutch_capacity_exponent)
    if int(p.hill_start_assist_release_mode) == RELEASE_LOAD_ADAPTIVE:
        at_release_point = cap >= p.hill_start_assist_release_load_frac * t_hold
    else:
        x_rel = p.hill_start_assist_release_position_frac[gear - 1] if gear >= 1 else 1.0
        at_release_point = c.clutch_command_frac >= x_rel
    entry = brake_released_edge and standing and gear > 0

    # the engine: best governed torque above the launch speed, at the driver's pedal and at full pedal
    margin = p.hill_start_assist_hold_torque_margin_frac
    if check:
        best_now = engine_best_torque_nm(p, m.accelerator_frac, w_launch)
        best_full = engine_best_torque_nm(p, 1.0, w_launch)
        torque_ok = best_now >= margin * t_hold
        too_steep_at_entry = best_full < margin * t_hold
    else:  # seeded defect: the old comparison with the peak torque
        engine_max_nm = 0.0
        for i in range(int(p.engine_full_load_torque_n)):
            engine_max_nm = max(engine_max_nm, p.engine_full_load_torque_y[i])
        best_now = engine_max_nm
        torque_ok = True
        too_steep_at_entry = t_hold > p.hill_start_assist_max_hold_torque_frac * engine_max_nm
    if int(c.mode) == ENGAGE_HELD and at_release_point and m.hand_valve_released_flag > 0.5 and not torque_ok:
        c.torque_short_time_s += dt
    else:
        c.torque_short_time_s = 0.0
    slip_meas = m.engine_speed_radps - m.input_shaft_speed_radps
    # P10's second control variable (NaN when the input-shaft speed sensor is not valid: engine law alone)
    in_rate = c.input_speed_rate_radps2 if m.input_shaft_speed_ok > 0.5 else np.nan
    lock_ok = True
    if check:
        lock_ok = engine_ok and m.engine_speed_radps >= w_launch and min(
            full_load_torque_nm(p, m.engine_speed_radps),
            governor_gain_nm_per_radps(p, governed_speed_radps(p, m.accelerator_frac))
            * (governed_speed_radps(p, m.accelerator_frac) - w_launch)) \
            >= p.hill_start_assist_lockup_torque_margin_frac * t_hold
    backwards = m.vehicle_speed_mps < -p.hill_start_assist_rollback_catch_speed_mps
    # grade force the park brake must hold (downhill, after the rolling-resistance reaction)
    grade_force = m.vehicle_mass_kg * 9.81 * (math.sin(c.grade_estimate_rad)
                                              - p.body_rolling_resistance_coeff * math.cos(c.grade_estimate_rad))

    # the park brake alone cannot be expected to hold (issue 7): its rated force is below the measured grade force
    # m g sin(alpha) (no credit for the rolling resistance: at rest it builds up only with creep). The clutch then
    # carries the rest, with the start margin, up to what the engine carries above the launch speed
    park_short_n = m.vehicle_mass_kg * 9.81 * math.sin(c.grade_estimate_rad) - p.park_brake_max_force_n
    x_support = 0.0
    if park_short_n > 0.0 and ratio > 0.0:
        x_support = _position(p, p.hill_start_assist_hold_torque_margin_frac * park_short_n * p.body_wheel_radius_m
                              / (ratio * p.gearbox_efficiency_frac))

    g = c.guards
    g[:] = 0.0
    g[G_SWITCH_FAILED] = entry and m.park_lamp_ok < 0.5
    g[G_RESERVOIR_LOW] = entry and park_applied and (
        m.reservoir_pressure_ok < 0.5 or m.reservoir_pressure_pa < p.hill_start_assist_reservoir_min_pa)
    g[G_ENGINE_LOST_ENTRY] = entry and park_applied and not engine_ok
    g[G_ENTRY] = entry and park_applied
    g[G_NORMAL] = entry and not park_applied
    g[G_STOPPED] = standing and brake_applied
    g[G_ROLLBACK] = catch_on and backwards
    g[G_TOO_STEEP] = too_steep_at_entry or (c.torque_short_time_s > p.hill_start_assist_refusal_delay_s)
    # lamp out while the valve should hold; in CATCH: the spring brake is not back on within the refusal delay
    g[G_VALVE_NOT_HOLDING] = m.park_lamp_ok > 0.5 and not park_applied and (
        int(c.mode) != CATCH or c.mode_time_s > p.hill_start_assist_refusal_delay_s)
    g[G_ENGINE_LOST] = not engine_ok
    # the park lamp should go out within the paper's Table-1 release time for the measured reservoir pressure
    expected_release_s = interp(p.hill_start_assist_release_time_x, p.hill_start_assist_release_time_y,
                                p.hill_start_assist_release_time_n, p.hill_start_assist_release_time_extrap,
                                p.hill_start_assist_release_time_interp, m.reservoir_pressure_pa)
    g[G_NOT_RELEASED] = (c.mode_time_s > expected_release_s + p.hill_start_assist_release_timeout_margin_s
                         and park_applied and standing)
    g[G_DRIVER_BRAKES] = brake_applied
    g[G_ACCELERATOR] = m.accelerator_frac >= p.hill_start_assist_accelerator_on_frac
    g[G_KISS] = c.clutch_command_frac >= p.clutch_kiss_point_frac
    g[G_RELEASE] = at_release_point and m.hand_valve_released_flag > 0.5 and torque_ok
    # before the AMT's own 550 rpm opening; only on a grade that rolls the truck back (grade force above the
    # rolling resistance) and with the driver on the accelerator: a driver who lifts off lets the engine fall to
    # idle (the guard speed) while coasting, and the spring brake must not be applied under a moving truck then
    # (review of issue 7: with 't_hold > 0' alone it was, on a level road, 70-83 kN at the rear tandem); a truck
    # that then stops and rolls back is caught by rollback_detected
    g[G_PULLED_DOWN] = (catch_on and engine_ok and m.engine_speed_radps < p.hill_start_assist_guard_speed_radps
                        and grade_force > 0.0 and m.accelerator_frac >= p.hill_start_assist_accelerator_on_frac
                        and not brake_applied)
    g[G_SLIP_SMALL] = (abs(slip_meas) <= p.hill_start_assist_lockup_slip_radps
                       and m.vehicle_speed_mps > p.hill_start_assist_moving_speed_mps and lock_ok)
    g[G_CLOSED] = c.clutch_command_frac >= 1.0 and (int(c.mode) != STOOD_DOWN
                                                    or int(c.stand_down_action) == STAND_DOWN_DRIVE_ON)
    g[G_BEYOND_PARK] = grade_force > p.park_brake_max_force_n
    # caught: the truck has stood still, with the lamp on, for the refusal delay (the energised valve had time to
    # exhaust the chambers: the spring brake is fully back on)
    settled = c.mode_time_s >= p.hill_start_assist_refusal_delay_s
    spinning = not park_applied and standing and engine_ok and m.engine_speed_radps >= w_launch and \
        cap >= p.hill_start_assist_lockup_torque_margin_frac * t_hold
    c.spin_time_s = c.spin_time_s + dt if (spinning and int(c.mode) == ENGAGE_RELEASING) else 0.0
    caught = park_applied and c.standing_time_s >= p.hill_start_assist_refusal_delay_s and settled
    mode_now = int(c.mode)
    g[G_BEYOND_ADHESION] = (
        # CATCH: the spring brake is back on (lamp on) and the clutch resists, yet the truck still slides back
        (mode_now == CATCH and settled and park_applied and backwards)
        # ENGAGE_RELEASING: the park brake has let go (lamp out) and the clutch delivers more than the grade needs,
        # yet the truck stands: the driven wheels spin
        or (mode_now == ENGAGE_RELEASING and c.spin_time_s >= p.hill_start_assist_refusal_delay_s))
    g[G_CAUGHT] = caught
    # the driver takes over by braking, or by moving the hand valve back to park (an action, not a state)
    g[G_TAKES_OVER] = brake_applied or (c.hand_valve_was_released_flag > 0.5 and m.hand_valve_released_flag < 0.5)

    mode = int(c.mode)
    new_mode, guard = next_mode(TABLE, mode, g)
    if new_mode != mode:
        n_events = log_event(events, n_events, t, machine_id, mode, new_mode, guard)
        c.mode = new_mode
        c.mode_time_s = 0.0
        if new_mode == ENGAGE_RELEASING:
            c.release_commanded_flag = 1.0
        elif new_mode == STANDBY:
            c.release_commanded_flag = 0.0
            c.refusal_code = 0.0
        elif new_mode == STOOD_DOWN:
            if mode == STANDBY:
                c.stand_down_action = STAND_DOWN_PASSIVE
            elif guard == G_VALVE_NOT_HOLDING:
                c.stand_down_action = STAND_DOWN_DRIVE_ON
            elif guard == G_ENGINE_LOST and mode == ENGAGE_RELEASING:
                c.stand_down_action = STAND_DOWN_DRIVE_ON
            elif guard == G_BEYOND_PARK or guard == G_BEYOND_ADHESION:
                c.stand_down_action = STAND_DOWN_RESIST
            elif guard == G_NOT_RELEASED:
                # the chambers fill too slowly (restricted line, stuck relay valve) or not at all: re-apply the spring
                # brake through the 3/2 valve and keep the clutch resisting until it is back on. Opening the clutch
                # with the valve de-energised let a slowly filling brake release later under an open clutch
                # (review of issue 7: 175-339 m rollback with tau_fill 4-10 s, none without the assist)
                c.stand_down_action = STAND_DOWN_RESIST
                c.valve_command_flag = 1.0
            else:
                c.stand_down_action = STAND_DOWN_HOLD
            for k in range(len(REFUSAL_GUARDS)):
                if guard == REFUSAL_GUARDS[k]:
                    c.refusal_code = k + 1.0
    else:
        c.mode_time_s += dt
    c.brake_was_applied_flag = 1.0 if brake_applied else 0.0
    c.hand_valve_was_released_flag = 1.0 if m.hand_valve_released_flag > 0.5 else 0.0

    # outputs: 3/2 valve and clutch command
    x = c.clutch_command_frac
    held = new_mode == HOLD or new_mode == APPROACH or new_mode == ENGAGE_HELD or new_mode == CATCH
    # clutch torque the engine carries above the launch speed at the driver's pedal (issue 7)
    x_ceiling = _position(p, p.hill_start_assist_ceiling_frac * best_now) if check else 1.0
    if new_mode == STOOD_DOWN:
        action = int(c.stand_down_action)
        # keep holding what was held; a refusal (re-)applies the spring brake
        held = (action == STAND_DOWN_HOLD or action == STAND_DOWN_RESIST) and (
            c.valve_command_flag > 0.5 or c.refusal_code > 0.0)
        if action == STAND_DOWN_HOLD and held and ((catch_on and backwards) or x_support > 0.0):
            # the applied park brake does not hold the truck, or cannot be expected to (rated force below the
            # measured grade force): resist with the clutch instead of opening it (issue 7: 40 t on 16 deg crept
            # back 1.5-3.9 cm on the 100 kN brake after a refusal, 0 m without the assist)
            action = STAND_DOWN_RESIST
            c.stand_down_action = STAND_DOWN_RESIST
        if action == STAND_DOWN_HOLD:
            x = 0.0
        elif action == STAND_DOWN_RESIST:
            x = _resist(p, c, x, m, engine_ok, park_applied, x_ceiling, dt, x_support)
        elif action == STAND_DOWN_DRIVE_ON:
            slip_small = abs(slip_meas) <= p.hill_start_assist_lockup_slip_radps
            if engine_ok and slip_small and m.vehicle_speed_mps > p.hill_start_assist_moving_speed_mps:
                x = x + p.hill_start_assist_lockup_rate_per_s * dt
            elif engine_ok:
                x = max(x + engagement_rate_per_s(p, m.engine_speed_radps, c.engine_speed_rate_radps2, in_rate) * dt,
                        p.clutch_kiss_point_frac)
                x = min(x, max(x_ceiling, p.clutch_kiss_point_frac))
            else:
                x = max(x + p.hill_start_assist_engage_rate_slow_per_s * dt, p.clutch_kiss_point_frac)
    elif new_mode == HOLD:
        x = 0.0
    elif new_mode == APPROACH:
        x = min(x + p.hill_start_assist_approach_rate_per_s * dt, p.clutch_kiss_point_frac)
    elif new_mode == ENGAGE_HELD:
        if m.hand_valve_released_flag < 0.5 and at_release_point:
            pass  # driver still holds the hand valve in park: wait at the release point (6.2)
        else:
            x = max(x + engagement_rate_per_s(p, m.engine_speed_radps, c.engine_speed_rate_radps2, in_rate) * dt,
                    p.clutch_kiss_point_frac)
            x = min(x, max(x_ceiling, p.clutch_kiss_point_frac))
    elif new_mode == ENGAGE_RELEASING:
        # while the park force falls, the anti-stall back-off never takes the clutch below the torque that
        # holds the truck on the measured grade: backing off here would roll the truck back
        floor = p.clutch_kiss_point_frac
        if m.vehicle_speed_mps < p.hill_start_assist_moving_speed_mps:
            floor = max(floor, _position(p, t_hold))
        x = max(x + engagement_rate_per_s(p, m.engine_speed_radps, c.engine_speed_rate_radps2, in_rate) * dt, min(floor, x))
        # P6: keep the reverse growth of the park force small. While the truck still stands on the releasing
        # park brake, engage no deeper than k x the holding torque; lifted if it moves or the lamp goes out
        # (only while the park brake still holds: once the lamp is out the estimate was too low, engage on)
        if (park_applied and abs(m.vehicle_speed_mps) < p.hill_start_assist_moving_speed_mps
                and m.vehicle_speed_mps > -p.hill_start_assist_standstill_speed_mps):
            ceiling = _position(p, p.hill_start_assist_phase3_torque_frac * t_hold)
            x = min(x, max(ceiling, c.clutch_command_frac)) if x > ceiling else x
        x = min(x, max(x_ceiling, min(floor, x)))  # never more than the engine carries above the launch speed
    elif new_mode == LOCKUP:
        if not check or abs(slip_meas) <= p.hill_start_assist_sync_slip_radps:
            x = x + p.hill_start_assist_lockup_rate_per_s * dt  # synchronised: clamp
        else:
            # synchronise: the clutch capacity follows the engine torque plus a small surplus that closes the
            # slip in about t_sync (no flywheel dump into the driveline)
            t_e = engine_available_torque_nm(p, m.engine_speed_radps, m.accelerator_frac)
            surplus = max(p.engine_inertia_kgm2 * abs(slip_meas) / p.hill_start_assist_sync_time_s,
                          p.hill_start_assist_sync_torque_min_nm)
            x = min(x + p.hill_start_assist_lockup_rate_per_s * dt, _position(p, t_e + surplus))
    elif new_mode == DONE:
        x = 1.0
    elif new_mode == CATCH:
        x = _resist(p, c, x, m, engine_ok, park_applied, x_ceiling, dt, x_support)
    c.clutch_command_frac = min(max(x, 0.0), 1.0)
    c.valve_command_flag = 1.0 if held else 0.0
    return n_events


@nb.njit(cache=True, nogil=True, error_model="numpy")
def is_active(c):
    """True while the assist (not the AMT's normal start program) drives the clutch."""
    mode = int(c.mode)
    if mode == STOOD_DOWN:
        return int(c.stand_down_action) != STAND_DOWN_PASSIVE
    return (mode == HOLD or mode == APPROACH or mode == ENGAGE_HELD or mode == ENGAGE_RELEASING or mode == LOCKUP
            or mode == CATCH)
