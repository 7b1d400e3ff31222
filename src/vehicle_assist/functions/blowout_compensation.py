"""Tire-blowout compensation by differential braking (paper 004; tire_blowout.md 4-5), hosted in the ESP
controller (functions/esp.py), on the measurement record only.

Formulas (pure, also used by the tests and the study):

* ``intact_braking_force_n``: Dugoff closed forms at alpha = 0 per wheel, both H branches (spec 4):
  H = mu*F_z*(1 - s)/(2*C_x*s); H >= 1: C_x*s/(1 - s); H < 1: mu*F_z - (mu*F_z)^2*(1 - s)/(4*C_x*s).
* ``added_yaw_moment_nm`` (eqs. 22-25, any blown wheel, branch per intact wheel):
  M_z_blow = b_f*(F_b_fl - F_b_fr) + b_r*(F_b_rl - F_b_rr), blown wheel F_b = mu_blow*F'_z (s = 1).
* ``required_pressure_pa`` (eqs. 26-28): p_w = M_z_blow*R_w/(b*K_b), K_b = A_p*r_b*mu_b*eta_b*n_f [N*m/Pa].
* ``valve_pressure_pa`` / ``valve_time_s`` (eqs. 29-30): two-segment build after the inlet valve opens and
  its inverse; p1 = 0.45*p_max, p2 = 0.9*p_max; above p2 the time saturates at t2 (flag).

Controller, on the measurement record only (``reference_step`` then ``blowout_step`` every ESP period):

Reference speed (``reference_step``, state ``S_VREF``): the car's speed from the wheels that are not known or
suspected to be blown (the detected wheel, else the wheel the TPMS names), rate-bounded both ways:
v = clip(max of those wheels, v_prev - (|a_x| + margin)*dt, v_prev + (max(a_x, 0) + RISE_MARGIN)*dt). The
deceleration bound is the ESP's (std ABS practice); the rise bound means a blown wheel, whose smaller radius
makes it read up to (R_out/R_in - 1) ~ 50 % fast within the deflation time, cannot drag the reference up
before it is found. The ESP uses this reference for ABS while a wheel is excluded, and the estimate takes the
intact wheels' slip from it (issue #10 review: the old reference included the blown wheel until one period
after detection, so a braking driver's slips read ~0.3 and the estimate collapsed).

Detection: the wheel-speed signature is a wheel faster than max(v_ref, median of the others) by
``wheel_speed_threshold`` (its rolling radius fell; the reference keeps deep ABS slip of the others from
making an intact wheel look fast); the TPMS alarm names a wheel. ``detection`` = wheel speeds, TPMS, or both
(agreement required). With both, while the driver brakes (brake-light switch) a braked blown wheel shows no
over-speed (it is braked or locked), so the TPMS alarm alone detects ("TPMS path"); such a detection counts as
single-source (the yaw-plausibility check below applies). The candidate must persist for ``detection_delay_s``.

Modes (``MACHINE``, rows exercised one by one in tests/functions/test_blowout_compensation.py):
IDLE -> BUILD (blowout_detected): the ECU computes loads (nominal data, measured a_x), the transfer f
(eqs. 13-20), M_z_blow at the intact wheels' mean measured slip (eqs. 22-25, branch per wheel), the added
pressure p_w (eq. 28, zero if the moment already points away from the blown side) on top of the opposite
wheel's present pressure p_0 (the ECU's estimate: the driver's pressure if braking), and the valve time
t(p_0 + p_w) - t(p_0) (eq. 30); the opposite wheel of the same axle gets an accumulator build for it.
IDLE -> LIMITED (inlet_valve_stuck): the opposite wheel's inlet is diagnosed stuck closed at detection: the
intact wheel of the other axle on the opposite side takes over, capped at the ECU's lock estimate
mu*F'_z*R/K_b (authority limited: its moment arm/brake are smaller) - limit code 1 and the guard name say why;
code 2 if that wheel's inlet is stuck as well (no authority). BUILD/HOLD -> LIMITED (inlet_valve_stuck): the
same diagnosis arriving after the detection. With a REAR blown (the substitute a front) the front on the
blown side - its brake a moment toward the blown side - is released beyond the ESP's yaw rates (``substitute_yaw_limit``,
``substitute_yaw_limit_flag``, 0 = the code before; tire_blowout_findings.md K2). The DIAGONAL fault (a REAR blown, the
OTHER side's front stuck, the driver braking: the pedal brakes the blown side's front alone, a moment toward the blown
side) takes the same yaw limitation on that front against the stuck one (``diagonal_fault``, ``diagonal_fault_flag``,
0 = the code before; tire_blowout_findings.md M1).
BUILD -> HOLD (valve_time_elapsed).
BUILD/HOLD/LIMITED -> REJECTED (yaw_implausible), single-source detections only: the car yaws away from the
presumed blown side by more than ``abort_yaw_rate`` (yaw rate minus the steady-state yaw rate of the measured
steer angle, ``reference_yaw_rate``, so a curve does not count) - a false detection: the brake is released AND the blown
latch is cleared, so the wheel is no longer held released and ABS/HBA run on all four wheels as without the
function (review finding: the latch stayed and the healthy wheel was never braked again, 5.86 m off the lane
when the driver then braked); the rejected wheel is remembered so the same single-source signature does not
re-trigger. With TPMS and wheel speeds agreeing the detection is trusted (an over-compensation at low mu is
left to ABS: releasing let the car drift 3.2 m, falsification finding).
Yaw judged net of the function's own release (``yaw_net_flag``, 0 = seeded defect = the raw yaw; issue #10 review
finding A): with a braking driver the detection is TPMS-only, and releasing the blown wheel from the driver's pressure
is itself a moment away from the blown side, b*K_b*dp/R (``released_moment_nm``: dp = the driver's share of the
same-axle wheel's pressure estimate minus the blown wheel's); its yaw rate in the ECU's single-track model
(``own_yaw_step``, nominal data) is added back before the threshold once the released wheel shows the blowout's
over-speed for ``detection_delay_s`` (a released healthy wheel does not: a false alarm stays judged on the raw yaw) and
while the same-axle braked wheel is in its linear region (``_opposite_linear``; beyond it the model does not hold), so
a real blowout is not rejected for the yaw the release makes (RL 119 km/h, pedal at t_b - 15 ms: 1.39 -> 0.64 m, none
1.19 m). The compensation pressure stays in the judged yaw: it balances a real blowout's moment and is the unbalanced
moment of a false detection. Past the linear region (``release_bound_flag``, 0 = seeded defect = the raw yaw there) the
release is netted with its friction-circle lower bound (``released_moment_bound_nm``: half-track * |a_x|/g * F_z - a
saturated tire carries mu*F_z and mu >= |a_x|/g), except while the steered reference yaw points toward the blown side
(a curve toward it: a saturated front's understeer reads as yaw away, the raw yaw decides); random 61 b128 #101, FL
110 km/h mu 0.58 straight, pedal from t_b - 0.15 s: rejected at t_b + 0.85 s, 4.34 m -> not rejected, 1.99 m (none 8.51).
BUILD/HOLD/LIMITED -> REJECTED (signature_unconfirmed; ``tpms_confirm_flag``, 0 = seeded defect; tire_blowout_findings.md P,
session 2026-11-24 e): a TPMS-path detection (TPMS only, driver braking) is confirmed by the released wheel - a flat wheel
freed of the brake spins up toward its free-rolling speed ~50 % above the car's, a healthy one rolls at the car's speed.
Its filtered speed within ``wheel_speed_threshold_frac`` of v_ref with its filtered acceleration below a_x +
SPINUP_MARGIN_MPS2, its pressure down (free of the brake), for HEALTHY_PERSIST_S (``released_wheel_healthy``) rejects it as a false alarm (as yaw_implausible);
over-speed confirms it for good. A false RL alarm under an 80 N pedal was never rejected by the yaw (RR's counter-brake
held under the rear slip limit): 1.76 / 2.55 m at 100 / 120 km/h -> 0.015 / 0.020 m (the function off: 0.00 m).
After a rejection while braking the released wheel gets the driver's pressure back at once (``reject_reapply_flag``,
S_REAPPLY, functions/esp.py) up to the same-axle wheel's pressure: ABS had re-built it in pulses (front) or the rear
select-low held it low (false FL / RL alarm under 500 N at 100 km/h: 1.33 / 2.57 -> 0.54 / 0.87 m).
After a rear wheel's rejection while braking, until the brake is released (``reject_pair_low_flag``, S_PAIR_LOW,
functions/esp.py): the re-applied rear's ECU estimate is the re-apply's line model, and the rear select-low acts on the
pair's pressure (the higher rear dumped to the lower one's): ABS had dumped the pair before the line filled the
re-applied rear (35 of 81 bar) and the select-low then kept RL 25-35 bar below RR (false RL alarm, 500 N, 100 / 120 km/h:
1.29 / 2.06 -> 0.19 / 0.16 m).
REJECTED -> IDLE (signature_cleared): no candidate on the rejected wheel for ``detection_delay_s``.
REJECTED -> BUILD / LIMITED: a blowout found on another wheel (same guards as from IDLE).
HOLD/LIMITED -> ENDED (vehicle_slow): reference speed below the minimum speed: compensation over; a real blown
wheel stays released (it is flat).
IDLE/REJECTED -> REFUSED and BUILD/HOLD/LIMITED -> REFUSED (beyond_stable_region; ``stability_refusal_flag``,
0 = defect): the car is beyond the stable region at the detection or leaves it during the compensation -
|r| > 0.85*mu*g/u (limit code 3) or |beta| > atan(0.02*mu*g) (code 4) (Rajamani, Vehicle Dynamics and Control,
2nd ed. 2012, ch. 8), measured r, beta = integral of a_y/u - r from the detection, mu = the ECU's nominal
mu_estimate_frac (``unstable_code``): the feed-forward cannot help a sliding car; nothing is planned / the target
wheel returns to the driver's pressure and ABS; a wheel confirmed by both sources stays
released (flat); a single-source detection is not held released (review finding 3) - except a blowout refused AT its
detection (``refused_blown_driver_flag``, 0 = seeded defect = released; session k K6): the function never acted, its
blown wheel stays with the driver and ABS, the car as without the function. Terminal for this blowout.
Spin-front rule (``spin_front_flag``, 0 = seeded defect = the refusal above; session 2026-11-24 e): a REAR blowout
compensated on the rear axle whose car is beyond those bounds rotating TOWARD the blown side (the spin the flat rear
tire starts) goes to LIMITED (same guard, limit code 5) instead of REFUSED: the rear compensating wheel is released (its
brake force takes friction circle from the axle that already lost the flat tire's lateral force) and the front wheel of
the same side - the outer front wheel of the spin - is braked to the ECU's lock estimate mu*F'_z*R/K_b, ABS guarding
it, as an ESP's oversteer intervention (Bosch Automotive Handbook, ESP; van Zanten, SAE 2000-01-1633): its brake
moment opposes the spin and its lost lateral force understeers. The tire-capacity limit does not apply to it; it is
dumped while the car turns back away from the blown side faster than the ESP's yaw dump rate; not refused while the
spin lasts (the ESP's GMA does not delay it, functions/esp.py). Front blowouts and rotation away from the blown side:
refused as before. Rear spin points (RL 101.9 / 110.7 km/h, 650 m): 18.84 / 21.73 m with the refusal, 7.72 / 6.78 m
with the rule, none 18.17 / 20.72 m (docs/functions/tire_blowout.md).
Its trigger also reads the friction-free sideslip phase plane (``phase_plane_unstable``, ``phase_plane_flag``, 0 = seeded
defect = the mu-0.8 bounds alone): |beta_dot + B1*beta| > B2 (Inagaki et al. 1994, dry road), beta_dot = a_y/u - r
measured - on mu 0.48 the mu-0.8 yaw bound was crossed only late in the slide (random 7 #7: 3.39 s, 17.33 m vs none
15.94; with it 2.36 s, 13.33 m). The refusal keeps the mu-0.8 bounds.
LIMITED (code 5) -> BUILD (spin_stopped; ``spin_exit_flag``, 0 = seeded defect = no exit, the front braked to the end
of the run; session 2026-11-24 f, ``spin_stopped``): the car back inside the stable region - the mu-0.8 bounds, the
phase plane, the yaw rate relative to the steered reference not toward the blown side beyond the closed-loop dead band
(an ESP ends its oversteer intervention once the yaw deviation is back in its dead band) and the yaw angle the spin
turned the car toward the blown side (S_PSI_ERR, the integral of that deviation from the detection) taken back - for
the 2 % settling time 8/a_1 of the ECU's single-track yaw mode (``settling_time_s``, 1.00 s at 120 km/h): the front
wheel is released - linearly over that same settling time (``spin_release_ramp_flag``, 0 = at once; released at once the
car yawed back toward the blown side on the held-driver 0.4 s points, 4 grid points worse than without the exit, none
with the ramp) - and the rear compensating wheel re-planned to the balance (eqs. 13-28, the rear limits guarding it);
a new spin moves the counter-brake to the front again. Fixed holds of 0.1-0.5 s without the heading condition exited
at the yaw swing-back and re-spun the car (RL 120 km/h 650 m, mu scale 0.3, held: 4.16-8.00 m vs 1.39 m without an
exit); the settling time without the heading condition: 1.95 m there, spin points 7.81 / 7.80 m (7.17 / 6.78 without
an exit). RL 120 km/h 650 m points (open item 5): 1.39 / 1.85 / 1.74 m -> 0.66 / 0.98 / 1.71 m (none 6.33 / 6.93 /
15.27 m); with the ramp 0.66 / 1.31 / 1.73 m. The rear balance after the exit is still planned at the nominal mu 0.8
(tire_blowout_findings.md Z, Z2). The ramp runs only in BUILD/HOLD (``ramp_refused_flag``, 0 = seeded defect = on in REFUSED/ENDED
too): a refusal after the exit (beyond the bounds rotating away from the blown side) releases the front at once; and
never below the driver's master pressure (``ramp_driver_floor_flag``, 0 = seeded defect = down to 0 under a braking
driver: FR 2.3 bar vs FL 25 bar, random 29 #37 2.020 m vs 1.374 m without the exit; floored 1.355 m).
Rear compensating wheel (``slip_limit_flag``, 0 = seeded defect; falsification of issue #10): its brake force is
kept below the slip where braking starts to cut its lateral force (Dugoff f(H) >= 1 - s; round 3 - with the nominal
mu alone this limit made two low-friction points worse than none in round 2, the measured tire capacity below now
guards them; round 2 used the H = 1 boundary) while it carries its
share of the rear axle's lateral force for the steered path (by cornering stiffness, the flat tire k_Cy),
``rear_linear_limit``: the planned added pressure is capped at that force, and every period a
measured slip above the matching slip dumps the added pressure (never below the driver's current pressure at
the wheel: the measured master pressure through the proportioning valve) and lowers the held
target. A rear wheel braked into saturation (12-18 % slip, below ABS's 20 %) left the axle with
the flat tire without lateral force and the car spun toward the blown side. Front targets are not limited by it
(less front lateral force is understeer, which does not spin the car).
Compensating wheel (front and rear) limited by what its tire measurably gives (``tire_capacity_flag``, 0 = seeded defect;
issue #10 round 3, ``tire_capacity_check`` / ``tire_capacity_rule``): the ECU plans from its nominal mu 0.8; on a
wet road that brakes the front wheel deep past its linear region and the lost front lateral force carries the car
out of a curve (CMA-ES seed 2026: 9 front points worse than none). From measurements only (derived: the Dugoff
saturation of spec 2.3 inverted, as the Dugoff fit in braking intervals of Villagra et al., Control Engineering
Practice 19 (2011); not Gustafsson's 1997 slip-slope method, which reads friction from the low-slip slope): F_x = (K_b*p_est + J*omega_dot)/R, slip from the wheel speed against the
reference, q = F_x/(C_x*s/(1 - s)) = Dugoff f(H); q < 0.8 (CAP_FORCE_RATIO) at s > 1 % for 20 ms with a measured
capacity mu*F_z = 2*H*C_x*s/(1 - s) (H = 1 - sqrt(1 - q)) below the nominal mu latches a low-friction limit: the
target drops to the H = 1 force mu_est*F_z/2 and to the plan re-scaled to mu_est (never below the driver's pressure),
above it the added pressure is dumped. Not while the driver brakes (the wheel's pressure is then partly the
driver's). Brake-gain tolerance (``brake_gain_tolerance_frac``, 0 = seeded defect): a front wheel's evidence (q and
mu_est) is judged with (1 + tol) x the nominal gain, the most pad friction the tolerance allows (SAE J866 code F upper
edge 0.45 over mu_b 0.38: tol 0.18), since more pad friction than nominal under-states F_x and read a linear tire on
the paper's cement road as saturated (+13 % pad friction: paper test 0.28 -> 1.68 m); the lowered target keeps the
nominal estimate. A rear wheel is judged at the nominal gain: a missed rear saturation spins the car, and its target
is already held in its linear region by the rear slip limit. A rear target is also held to ``rear_linear_limit_mu`` at the measured friction (its lateral share).
Wheel-speed noise (``signal_filter_flag``, 0 = seeded defect = raw samples; issue #10 independent review): both limits
above judge filtered wheel signals - a moving mean over WS_WINDOW_N = 8 ESP periods per wheel (speed, slip, the ECU's
pressure estimate on the same window) and the least-squares slope over the same window for the wheel deceleration
(``wheel_accel_mps2``); the compensating wheel's slip is taken against the mean of the two free-rolling intact wheels
when the driver does not brake (``slip_reference_mps``; the rate-bounded max reference rides the upper edge of the
noise), the reference speed is the rate-bounded max of the moving means carried to now with the measured a_x. The rear
limit acts after SLIP_PERSIST_S above its cap (hysteresis SLIP_HYST_FRAC), lowers the target to the window's pressure
scaled to the cap slip, and lowers it again only on a fresh window (latched otherwise: re-building into a rear tire at
its limit is what started the spins of the falsification, docs/functions/tire_blowout.md). 0.1 / 0.2 rad/s of noise on
the four wheel speeds had taken the shipped RR 60 km/h run from 0.72 m to 2.46 / 7.47 m (= none); now 0.45 / 0.52 /
0.70 m at 0 / 0.1 / 0.2 rad/s.
Front blowout with a braking driver (``braking_rule_flag``, 0 = seeded defect; ``braking_rule``, read by the ESP
arbitration): from the yaw-moment balance of the four brake forces with the blown wheel unbraked,
M_z = b_f*(D - F_opp) + b_r*(F_rl - F_rr): the compensating front wheel = drag balance (eqs. 26-28) + a share of the
driver's pressure within its friction circle, the share only while the measured yaw does not point away from the blown
side, re-built after an ABS dump to its pressure at the dump's start; the rear pair one cap at the friction circle
with its lateral share at the measured friction (``rear_circle_flag``; 0 = seeded defect = the linear-region cap);
in an oversteer toward the blown side (outside the sideslip phase-plane region, Inagaki 1994, the slide of the spin
toward the blown side) the pair is held and lowered 1 bar per period, also before any measured friction
(``rear_oversteer_flag``, ``rear_oversteer_cap``; 0 = seeded defect = no rear cap without a measured friction).
Understeer rule (``understeer_flag``, 0 = seeded defect = the code before; ``understeer_rule``; tire_blowout_findings.md R3/X): a
FRONT blowout compensated on the other front wheel, driver not braking, the capacity rule having measured a friction
below the nominal on that wheel, the steering reference (``reference_yaw_rate``) toward the blown side (the blown wheel
is on the inside of the steered turn) and the measured yaw rate short of it by more than the dead band: the car
understeers - ESP practice answers that with a moment into the turn, never on the outer front (van Zanten, SAE
2000-01-1633) - and the blown inner front's drag is such a moment, while the outer front's brake force takes friction
circle from the front axle that carries the curve. The target is lowered to the present pressure and the added pressure
dumped; within the dead band held; restored to the balance before the lowering once the car turns toward the blown side
beyond the reference by the dead band. Lead random 41 b512 #336 (FL 119.6 km/h mu 0.322 r650 follower): 1.31 -> 0.18 m
(none 0.66). While the target is held lowered the capacity rule does not lower its latched cap
(``understeer_cap_freeze_flag``, 0 = seeded defect): the held wheel's pure-longitudinal inversion reads its friction
direction, which falls with the dumped pressure, not its capacity; after the restore a fresh filter window first.
Optional closed loop (``closed_loop_flag``): in HOLD, yaw toward the blown side above the deadband adds
pulsed build on the braking wheel, yaw away from it dumps; otherwise hold.
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.conventions import G_MPS2, RHO_AIR_KGPM3
from vehicle_assist.core.fsm import StateMachine, Transition, log_event
from vehicle_assist.plant.brakes.master_cylinder import proportioned_pa
from vehicle_assist.plant.tires.blowout import OPPOSITE, redistributed_loads, transfer_n

IDLE, BUILD, HOLD, LIMITED, REJECTED, ENDED, REFUSED = range(7)
MODES = ("IDLE", "BUILD", "HOLD", "LIMITED", "REJECTED", "ENDED", "REFUSED")
MACHINE = StateMachine("blowout_compensation", MODES, (
    Transition("IDLE", "BUILD", "blowout_detected", "wheel speed and/or TPMS name a blown wheel for detection_delay_s"),
    Transition("IDLE", "LIMITED", "inlet_valve_stuck", "opposite wheel's inlet diagnosed stuck closed: same-side other axle, capped"),
    Transition("BUILD", "HOLD", "valve_time_elapsed", "inlet open for t_valve (eq. 30), then hold"),
    Transition("BUILD", "LIMITED", "inlet_valve_stuck", "opposite inlet diagnosed stuck during the build: other axle, capped"),
    Transition("HOLD", "LIMITED", "inlet_valve_stuck", "opposite inlet diagnosed stuck during the hold: other axle, capped"),
    Transition("BUILD", "REJECTED", "yaw_implausible", "as from HOLD, already during the build (independent review: 20 ms earlier on a false TPMS alarm)"),
    Transition("HOLD", "REJECTED", "yaw_implausible", "single-source detection, car yaws away from the presumed blown side: release, latch cleared"),
    Transition("LIMITED", "REJECTED", "yaw_implausible", "as from HOLD"),
    Transition("HOLD", "ENDED", "vehicle_slow", "reference speed below the minimum speed; a real blown wheel stays released"),
    Transition("LIMITED", "ENDED", "vehicle_slow", "reference speed below the minimum speed"),
    Transition("REJECTED", "IDLE", "signature_cleared", "no candidate on the rejected wheel for detection_delay_s"),
    Transition("REJECTED", "BUILD", "blowout_detected", "a blowout found on another wheel"),
    Transition("REJECTED", "LIMITED", "inlet_valve_stuck", "a blowout found on another wheel, its opposite inlet stuck"),
    Transition("IDLE", "REFUSED", "beyond_stable_region", "at detection the car is already beyond the stable region "
               "(stability_bounds): no feed-forward, the blown wheel released, the others the driver's and ABS's"),
    Transition("REJECTED", "REFUSED", "beyond_stable_region", "as from IDLE"),
    Transition("BUILD", "REFUSED", "beyond_stable_region", "the car leaves the stable region during the build: stand down"),
    Transition("HOLD", "REFUSED", "beyond_stable_region", "as from BUILD"),
    Transition("LIMITED", "REFUSED", "beyond_stable_region", "as from BUILD"),
    Transition("BUILD", "LIMITED", "beyond_stable_region", "rear blowout, rear compensating wheel, the car leaves the "
               "stable region rotating toward the blown side (spin_front_flag): the rear wheel released, the front "
               "wheel of its side braked to the ECU's lock estimate (ESP oversteer practice), limit code 5"),
    Transition("HOLD", "LIMITED", "beyond_stable_region", "as from BUILD"),
    Transition("IDLE", "LIMITED", "beyond_stable_region", "as from BUILD, the car already beyond at the detection"),
    Transition("REJECTED", "LIMITED", "beyond_stable_region", "as from IDLE"),
    Transition("BUILD", "REJECTED", "signature_unconfirmed", "TPMS-path detection while braking (tpms_confirm_flag): the "
               "released wheel rolls at the car's speed without spinning up (a released flat wheel spins up to ~50 % "
               "over-speed): a healthy wheel, false TPMS alarm - release, latch cleared, as yaw_implausible"),
    Transition("HOLD", "REJECTED", "signature_unconfirmed", "as from BUILD"),
    Transition("LIMITED", "REJECTED", "signature_unconfirmed", "as from BUILD"),
    Transition("LIMITED", "BUILD", "spin_stopped", "spin-front wheel (limit code 5), the car back inside the stable "
               "region - the mu-0.8 bounds, the sideslip phase plane, no yaw toward the blown side beyond the "
               "closed-loop dead band, the spin's heading taken back - for the single-track model's settling time "
               "(spin_exit_flag): the front released, the rear compensating wheel re-planned to the balance (eq. 28)"),
    Transition("BUILD", "REJECTED", "blown_side_unbraked", "single-source detection of a blown REAR whose side's "
               "FRONT inlet is diagnosed stuck with no brake in it, the driver braking (blown_side_single_flag): the "
               "paper's release leaves that side unbraked - the function stands down as REJECTED does"),
    Transition("HOLD", "REJECTED", "blown_side_unbraked", "as from BUILD"),
    Transition("LIMITED", "REJECTED", "blown_side_unbraked", "as from BUILD"),
))
G_DETECTED, G_STUCK, G_VALVE_DONE, G_YAW_IMPLAUSIBLE, G_SLOW, G_CLEARED, G_UNSTABLE, G_UNCONFIRMED, G_SPIN_STOPPED, \
    G_BLOWN_SIDE_UNBRAKED = range(10)
REASONS = MACHINE.guards
# per-wheel requests to the ESP arbitration
Q_NONE, Q_BUILD, Q_HOLD, Q_RELEASE, Q_PULSE = range(5)
# state vector
S_MODE, S_BLOWN, S_SUSPECT, S_SUSPECT_S, S_T_DET, S_M_EST, S_P_REQ, S_T_VALVE, S_ELAPSED, S_TARGET, S_SATURATED, \
    S_SLIP_EST, S_LIMIT_CODE, S_MODE_ELAPSED, S_VREF, S_STARTED, S_EXCLUDED, S_REJECTED, S_SOURCES, S_CLEAR_S, \
    S_P_ADD, S_P_START, S_SLIP_CAP, S_SLIP_LIMITED, S_FZ_TARGET, S_BETA_EST, S_VW_PREV, S_LOW_S, S_CAP_LATCHED, \
    S_F_CAP, S_BUF_LAST, S_BUF_FILL, S_SLIP_HIGH_S = range(33)
# wheel-signal filter (``signal_filter_flag``): ring buffers of the last WS_WINDOW_N wheel speeds [m/s] and the ECU's
# wheel-pressure estimates [Pa], 4 wheels each, written every ESP period (reference_step / blowout_step)
WS_WINDOW_N = 8  # assumed: 8 ESP periods = 40 ms: the moving mean cuts white wheel-speed noise by sqrt(8) = 2.8 and
#   the least-squares slope's noise to 1/(dt*sqrt(N*(N^2 - 1)/12)) = 1/(6.5*dt) of a sample's, 9 x less than the
#   one-period difference (sqrt(2)/dt); the window (centre 17.5 ms old) is short against the valve build
#   (t2 = 0.2 s, tire_blowout.md 7) and the 50 ms detection delay
S_VW_BUF = 33
S_P_BUF = S_VW_BUF + 4 * WS_WINDOW_N
# the ECU's single-track model of the function's own yaw moment (``yaw_net_flag``, ``own_yaw_step``): sideslip [rad]
# and yaw rate [rad/s], CCW +, integrated from the detection
S_BETA_OWN = S_P_BUF + 4 * WS_WINDOW_N
S_R_OWN = S_BETA_OWN + 1
S_OVERSPEED_S = S_R_OWN + 1  # how long the released blown wheel has shown the blowout's over-speed [s] (yaw_net_flag)
# braking rule (``braking_rule_flag``, ``braking_rule``): the compensating front wheel's pressure target while the driver
# brakes [Pa] (-1 = none), the lowest friction the capacity rule measured (0 = none), the rear pair's cap [Pa] (-1 none)
# and the compensating wheel's pressure when ABS last started a dump on it (re-build target) [Pa] (-1 none)
S_P_BRAKE = S_OVERSPEED_S + 1
S_MU_MEAS = S_P_BRAKE + 1
S_REAR_CAP = S_MU_MEAS + 1
S_P_PREDUMP = S_REAR_CAP + 1
# TPMS-path confirmation (``tpms_confirm_flag``): how long the released wheel of a TPMS-only detection made while braking
# has rolled at the car's speed without spinning up [s]; -1 = not pending (no such detection, or confirmed by over-speed)
S_HEALTHY_S = S_P_PREDUMP + 1
# re-apply after a rejection while braking (``reject_reapply_flag``): the wheel the rejected detection had released, to be
# given the driver's pressure back at once up to the same-axle wheel's pressure (functions/esp.py); -1 none
S_REAPPLY = S_HEALTHY_S + 1
S_REAPPLY_P = S_REAPPLY + 1  # the ECU's line model of that wheel's pressure during the re-apply [Pa] (-1 = not started)
# rear select-low on the pair's pressure after a rear wheel's rejection while braking (``reject_pair_low_flag``,
# functions/esp.py): 1 until the brake is released, 0 otherwise
S_PAIR_LOW = S_REAPPLY_P + 1
# understeer rule (``understeer_flag``, ``understeer_rule``): 1 while the compensating outer front's target is lowered
# after an understeer, 0 otherwise
S_US_LIMITED = S_PAIR_LOW + 1
S_US_PLAN = S_US_LIMITED + 1  # the compensating wheel's target before the understeer rule lowered it [Pa]
# braking rule, rear pair in an oversteer toward the blown side (``rear_oversteer_flag``): the kinematic sideslip rate
# a_y/u - r of the last period [rad/s] (the phase-plane state with S_BETA_EST) and the cap it set on the pair [Pa] (-1 none)
S_BETA_DOT = S_US_PLAN + 1
S_REAR_OS_CAP = S_BETA_DOT + 1
# how long the car has been back inside the stable region while the spin-front wheel is braked [s] (spin_exit_flag)
S_SPIN_OK_S = S_REAR_OS_CAP + 1
# yaw angle the car has turned toward the blown side relative to the steered reference since the detection [rad]
S_PSI_ERR = S_SPIN_OK_S + 1
# 1 once the spin-front rule has ended (spin_exit_flag) and the rear is compensating again
S_SPIN_EXITED = S_PSI_ERR + 1
# ramped release of the spin-front wheel after the exit (spin_release_ramp_flag): its pressure at the exit [Pa], the
# time since the exit [s] and the ramp's duration, the settling time 8/a_1 at the exit speed [s]
S_RAMP_P0 = S_SPIN_EXITED + 1
S_RAMP_T = S_RAMP_P0 + 1
S_RAMP_DUR = S_RAMP_T + 1
S_RB_HIGH = S_RAMP_DUR + 1  # rear_braking_rule: the highest driver's pressure the rear compensating wheel reached [Pa]
# ABS activity per wheel as the ESP sees it (spec 4.3: a hold or dump in the last 0.3 s; 1/0), written by functions/
# esp.py before each blowout_step (blown_front_hold_flag: is the compensating front at its ABS limit)
S_ABS_ACTIVE = S_RB_HIGH + 1  # 4 slots, fl fr rl rr
# rear_oversteer_yaw_flag: 1 once the yaw rate exceeded the steered reference toward the blown side after the build (the
# rear pair held, ``rear_oversteer_cap``) - the released wheel's real flat, not a false alarm (0 otherwise)
S_OS_YAW_SEEN = S_ABS_ACTIVE + 4
# measured_mu_raise_flag: time the compensating front has measurably been linear while the driver brakes [s]
S_LIN_S = S_OS_YAW_SEEN + 1
# front_spin_keep_arrest_flag: time [s] a running front compensation has been kept beyond the stable region in HOLD
# (front_spin_keep) and the highest yaw rate toward the blown side seen while kept
S_KEEP_S = S_LIN_S + 1
S_KEEP_PEAK = S_KEEP_S + 1
# measured_mu_lower_flag: the braking rule's measured friction before the first raise of this pedal application (the
# floor the raise is taken back to after an ABS dump of the compensating front; -1 = not raised)
S_MU_PRE = S_KEEP_PEAK + 1
# understeer_persist_flag: time [s] the understeer rule's yaw shortfall (reference toward the blown side, measured yaw short
# of it beyond the dead band) has lasted without a break in HOLD
S_US_SHORT_S = S_MU_PRE + 1
# understeer_persist_flag: time [s] the yaw has exceeded the reference toward the blown side beyond the dead band without
# a break (the restore of a lowering made without capacity evidence waits for the same settling time)
S_US_OVER_S = S_US_SHORT_S + 1
# braking_lock_floor_flag (``braking_rule``): the compensating front's pressure when ABS last started a dump on it (any
# dump: the lock level ABS found) [Pa] (-1 none: forgotten once ABS is quiet on the wheel - with braking_lock_keep_flag
# only once it is quiet AND the wheel is above the floor + 1 bar - and whenever braking_rule stops), its pressure
# estimate of the last period [Pa] (-1 none) and 1 while that estimate is falling (a dump under way, its start taken)
S_LOCK_P = S_US_OVER_S + 1
S_LOCK_PREV = S_LOCK_P + 1
S_LOCK_FALL = S_LOCK_PREV + 1
# abs_dump_bound_flag: the compensating wheel's measured deceleration [m/s^2, wheel circumference, > 0 = slowing] at
# the start of the ABS dump that set S_P_PREDUMP (functions/esp.py writes both at the same period)
S_AW_PREDUMP = S_LOCK_FALL + 1
# abs_dump_noise_flag: the same dump's reading over the whole wheel-signal window (``dump_window_reading``, written by
# functions/esp.py with S_P_PREDUMP): the ECU's pressure estimate [Pa] and the wheel's deceleration [m/s^2, > 0 =
# slowing], both weighted with the least-squares slope's interval weights
S_P_DUMPWIN = S_AW_PREDUMP + 1
S_AW_DUMPWIN = S_P_DUMPWIN + 1
DUMP_NOISE_SIGMAS = 3.0  # assumed (abs_dump_noise_flag): the dump reading's deceleration is taken 3 sigma of its
#   white-noise error above the reading (one-sided Gaussian: exceeded in 0.13 % of readings by noise alone), sigma from
#   the design wheel-speed noise blowout_compensation.abs_dump_speed_noise_radps (``dump_window_reading``)
# reject_heading_return_flag (session j, J5): the yaw-rate error toward the blown side at the detection (baseline: a
# constant gyro offset and the car's yaw error before the function acted cancel) [rad/s]; 1 while the heading the
# rejected detection's release + build turned the car away from the named wheel is being given back (0 otherwise); that
# heading, toward the named wheel + [rad]; the named wheel (-1 none)
S_GB_R0 = S_AW_DUMPWIN + 1
S_GB_ON = S_GB_R0 + 1
S_GB_PSI = S_GB_ON + 1
S_GB_B = S_GB_PSI + 1
# (esp.lock_level_line_flag) the ECU's line-lag wheel-pressure estimate A_P_LINE [Pa], 4 slots fl fr rl rr, written by
# functions/esp.py before blowout_step as S_ABS_ACTIVE: braking_lock_floor stores and compares its lock level on it
S_P_LINE = S_GB_B + 1
# (reject_heading_return_flag 2, session j J7) the speed reference at the detection [m/s]: the rule's steered reference
# keeps the understeer term of the linear single-track model at that speed (``heading_return_reference``)
S_GB_U0 = S_P_LINE + 4
# (heading_return_mean_baseline_flag, session j J9) the sum of the yaw-rate error (measured minus reference_yaw_rate)
# over the detection window of the present suspect [rad/s] and its number of samples: the baseline S_GB_R0 is their
# mean (the window the detection itself used, detection_delay_s), not the one sample at the detection
S_GB_RSUM = S_GB_U0 + 1
S_GB_RN = S_GB_RSUM + 1
# (heading_return_spin_exit_flag, session j J9) the time S_PSI_ERR counts from [s]: the detection, or a spin exit that
# reset S_PSI_ERR (the baseline is taken off the integral over that time only)
S_GB_T0 = S_GB_RN + 1
# (refused_blown_driver_flag, session k K6) 1 = this blowout was refused AT its detection (IDLE/REJECTED -> REFUSED):
# the function never acted on it, its blown wheel is left to the driver and ABS (Q_NONE), not released
S_REFUSED_DET = S_GB_T0 + 1
# (substitute_yaw_limit_flag 2, session k K7) the blown side's front's line-pressure level latched when the yaw error
# toward the blown side entered the band between esp.yaw_hold_rate and esp.yaw_dump_rate (or its level at the last dump
# period above esp.yaw_dump_rate) [Pa]; -1 = none (below esp.yaw_hold_rate)
S_SUB_HOLD = S_REFUSED_DET + 1
# (blown_side_fault_flag 3, session l L6) per wheel fl fr rl rr: the ECU's line-pressure estimate when its inlet was
# first diagnosed stuck closed - the pressure trapped in that wheel [Pa]; -1 = not diagnosed (yet)
S_L6_TRAPPED = S_SUB_HOLD + 1
# (front_substitute_rear_flag 2, session m M7) the yaw error toward the blown side [rad/s] (net of the steered reference)
# when the substitute rear's LIMITED code 1 first met the driver's pedal, and 1 = latched (0 = not yet / reset outside
# that LIMITED episode)
S_M7_ERR0 = S_L6_TRAPPED + 4
S_M7_SET = S_M7_ERR0 + 1
# (blown_side_front_flag 3, session m M2b) the blown wheel + 1 while the free rear's select-low gate is open for it (opened
# when the yaw error points away from the blown side beyond esp.yaw_hold_rate, closed beyond the dead band toward the
# blown side or when the rule stands aside, e.g. the pedal released); 0 = closed
S_M2B_GATE = S_M7_SET + 1
# (substitute_braking_flag 2, review R3, session n) the wheel rear_braking_rule's S_RB_HIGH / S_P_PREDUMP were taken on
# (the target wheel index), -1 = none; a new wheel starts them afresh
S_R3_RB_WHEEL = S_M2B_GATE + 1
STATE_SIZE = S_R3_RB_WHEEL + 1
# (heading_return_line_flag, session k K3) the fraction of the other front's pressure the heading return may take off the
# released front: with it the front axle keeps (2 - 0.5)/2 = 0.75 of its brake force, UN R13-H Annex 6 para 5.2's
# minimum adhesion utilisation epsilon >= 0.75 of an anti-lock car transposed onto the axle the rule acts on (assumed
# transposition: the paper and spec state no stopping bound for a false alarm)
HEADING_RETURN_AXLE_KEEP_FRAC = 0.5
SLIP_PERSIST_S = 0.02  # assumed: the rear slip limit acts after its filtered slip stays above the cap for 4 ESP periods
#   (as the capacity rule's CAP_PERSIST_S): one noisy sample above the cap no longer dumps and latches the target
RAW_SIGMAS = 6.0  # assumed: a raw slip sample above the cap by 6 x the noise the free wheels show acts at once (Gaussian
#   false-alarm probability ~1e-9 per sample, none in practice; 4 sigma was tried: noise 0.094 rad/s at 116 km/h then
#   triggered it and the envelope regression point cma2026_32_rr_gain075 was 1.98 m vs 1.57 m without compensation)
SLIP_HYST_FRAC = 0.1  # assumed: the limit, once acting, stops only below 0.9*cap (hysteresis; 10 % of a 3-5 % cap is
#   0.3-0.5 % slip, > 2 sigma of the filtered slip at 0.2 rad/s wheel-speed noise and 60 km/h)
# detection sources (S_SOURCES): bit 1 wheel speeds, bit 2 TPMS
SRC_WS, SRC_TPMS = 1, 2
ROLLING_RESISTANCE_MAX_FRAC = 0.018  # std (common.md 3.3): passenger-car rolling resistance f = 0.010-0.018 on asphalt /
#   concrete; the upper end bounds the part of the measured deceleration that no tire friction carries
#   (rear_accel_bound_flag, ``accel_friction_lower_bound``)
RISE_MARGIN_MPS2 = 2.0  # assumed: the BJ2500 cannot speed up faster than a_x,meas + 2 m/s^2 (0-100 km/h in ~14 s)
LIMIT_NONE, LIMIT_OTHER_AXLE, LIMIT_NO_AUTHORITY, LIMIT_YAW_BOUND, LIMIT_SIDESLIP_BOUND, LIMIT_SPIN_FRONT = 0, 1, 2, 3, 4, 5
LIMIT_BLOWN_SIDE = 6  # (blown_side_fault_flag, session l L1) the blown side's other wheel's inlet stuck closed
LIMIT_REASONS = ("none", "opposite inlet valve stuck closed: other-axle wheel of the same side, capped at its lock pressure; "
                 "the blown side's other-axle wheel yaw-limited (rear blown: its front released beyond the ESP's yaw "
                 "rates, substitute_yaw_limit_flag; front blown: its rear held at no more than the substitute, the car "
                 "braking on its rears alone, and released beyond the yaw dump rate, front_substitute_rear_flag)",
                 "opposite inlet valve and its substitute stuck closed: no braking authority",
                 "refused: yaw rate above the stable bound 0.85*mu*g/u (Rajamani 2012, 8.x)",
                 "refused: sideslip estimate above the stable bound atan(0.02*mu*g) (Rajamani 2012, 8.x)",
                 "beyond the stable region rotating toward the blown side (rear blowout): rear wheel released, the "
                 "front wheel of its side braked to its lock estimate (spin_front_flag)",
                 "the blown side's other inlet valve stuck closed: that side has no other brake - while the driver "
                 "brakes, rear blown: the blown wheel is left to the driver and ABS (not released) and no counter-brake "
                 "is added (blown_side_fault_flag); front blown: the paper's front balance stays (blown front released, "
                 "counter-brake front), the free rear held at no more than 1 bar above the stuck rear (rear select-low) "
                 "while the yaw error points away from the blown side (blown_side_front_flag)")
YAW_BOUND_FRAC = 0.85  # Rajamani, Vehicle Dynamics and Control (2nd ed. 2012), ch. 8 yaw control: |r| <= 0.85*mu*g/u
SIDESLIP_BOUND_S2_PER_M = 0.02  # same source: beta_max = atan(0.02*mu*g)
# measured tire capacity of the compensating wheel (tire_capacity_check / tire_capacity_rule)
CAP_FORCE_RATIO = 0.8  # assumed: measured F_x below 0.8*C_x*s/(1 - s) (Dugoff f(H) < 0.8) = clearly out of the linear
#   region: the ECU's nominal brake gain (pad friction) and C_x are each taken as known to ~10 %, so a ratio above 0.8
#   is not evidence of a saturating tire (the paper's own test runs its front wheel at 0.83 on the cement road)
CAP_MIN_SLIP = 0.01  # assumed: below 1 % the wheel-speed slip is within the wheel-radius/cornering spread of the wheels
CAP_PERSIST_S = 0.02  # assumed: 4 ESP periods of 5 ms below the ratio before latching (debounce of a derivative signal)
# TPMS-path confirmation (tpms_confirm_flag, ``released_wheel_healthy``)
SPINUP_MARGIN_MPS2 = 10.0  # derived: a released flat wheel spins up at F_x*R_in*R_out/J; even a flat tire carrying only
#   140 N of road force (R_in 0.24 m, R_out 0.359 m, J 1.2 kg*m^2, suv_bj2500) gives 10 m/s^2 above the car's a_x, while the
#   filtered slope's noise is 3.3 m/s^2 (1 sigma) at the envelope's 0.3 rad/s wheel-speed noise (WS_WINDOW_N note); the
#   measured flat wheels spin up at 40-50 m/s^2 (RL 119 km/h mu 0.49: 46 m/s^2 at 640 N)
HEALTHY_PERSIST_S = 0.02 + WS_WINDOW_N * 0.005  # assumed: 4 ESP periods (as CAP_PERSIST_S) after a whole filter window
#   (WS_WINDOW_N ESP periods of 5 ms) of samples taken with the wheel free of the brake: a flat rear wheel under a light
#   pedal rolls at ~v_ref while still braked (its own slip ~1/3) and starts to spin up only once its pressure is down
#   (CMA-ES seed 2026 #2/#11: RL/RR blowouts rejected 15-20 ms after the detection while the pressure still fell)
PRESSURE_MARGIN_PA = 1.0e5  # the 1-bar margin of the rules' pressure comparisons (release above a level + 1 bar, settled
# within 1 bar): the settling tolerance of spec 3 TERMINATING, criterion 7 (as functions/esp.py RAMP_SETTLED_PA)
RELEASED_MARGIN_PA = 1.0e5  # assumed: the released wheel counts as free of the brake below the unit's low-pressure
#   accumulator level + 1 bar (ECU pressure estimate; ~1 bar is < 4 % of a light pedal's rear pressure)


def initial_state() -> np.ndarray:
    st = np.zeros(STATE_SIZE)
    st[S_BLOWN] = -1.0
    st[S_SUSPECT] = -1.0
    st[S_TARGET] = -1.0
    st[S_SUB_HOLD] = -1.0
    st[S_L6_TRAPPED:S_L6_TRAPPED + 4] = -1.0
    st[S_M2B_GATE] = 0.0
    st[S_R3_RB_WHEEL] = -1.0
    st[S_EXCLUDED] = -1.0
    st[S_REJECTED] = -1.0
    st[S_BUF_LAST] = -1.0
    st[S_P_BRAKE] = -1.0
    st[S_REAR_CAP] = -1.0
    st[S_P_PREDUMP] = -1.0
    st[S_HEALTHY_S] = -1.0
    st[S_REAPPLY] = -1.0
    st[S_GB_B] = -1.0
    st[S_REAR_OS_CAP] = -1.0
    st[S_MU_PRE] = -1.0
    st[S_LOCK_P] = -1.0
    st[S_LOCK_PREV] = -1.0
    return st


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _push_wheels(st, vw):
    """Write this period's four wheel speeds into the ring buffer (called once per period, by reference_step)."""
    n = WS_WINDOW_N
    k = (int(st[S_BUF_LAST]) + 1) % n
    for i in range(4):
        st[S_VW_BUF + i * n + k] = vw[i]
    st[S_BUF_LAST] = k
    st[S_BUF_FILL] = min(st[S_BUF_FILL] + 1.0, float(n))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _push_pressures(st, p_est):
    """This period's wheel-pressure estimates into the slot of this period's wheel speeds (blowout_step)."""
    n = WS_WINDOW_N
    k = max(int(st[S_BUF_LAST]), 0)
    for i in range(4):
        st[S_P_BUF + i * n + k] = p_est[i]


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _window_mean(st, base, i):
    """Mean of wheel i's buffered samples (moving mean over the filled part of the window)."""
    n = WS_WINDOW_N
    m = max(int(st[S_BUF_FILL]), 1)
    k = int(st[S_BUF_LAST])
    acc = 0.0
    for j in range(m):
        acc += st[base + i * n + (k - j) % n]
    return acc / m


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_speed_mean(st, i):
    """Wheel i's speed [m/s], moving mean over the last WS_WINDOW_N ESP periods (value at the window centre)."""
    return _window_mean(st, S_VW_BUF, i)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_pressure_mean(st, i):
    """The ECU's wheel-pressure estimate of wheel i, averaged over the same window as ``wheel_speed_mean``."""
    return _window_mean(st, S_P_BUF, i)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_noise_mps(st, b, tg, dt):
    """The wheel-speed sensors' noise [m/s] as the ECU sees it: residual standard deviation of the least-squares lines
    of the two wheels that are neither blown (b) nor the compensating wheel (tg) over the window (they roll smoothly,
    the compensating wheel's own transient does not count); 0 until the window has 3 samples."""
    n = WS_WINDOW_N
    m = int(st[S_BUF_FILL])
    if m < 3 or b < 0 or tg < 0:
        return 0.0
    k = int(st[S_BUF_LAST])
    tbar = 0.5 * (m - 1)
    acc = 0.0
    for i in range(4):
        if i == b or i == tg:
            continue
        mean = wheel_speed_mean(st, i)
        slope = wheel_accel_mps2(st, i, 1.0)  # per period
        for j in range(m):
            res = st[S_VW_BUF + i * n + (k - j) % n] - (mean + slope * ((m - 1 - j) - tbar))
            acc += res * res
    return math.sqrt(acc / (2.0 * (m - 2)))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def slip_reference_mps(st, b, tg, v_ref, braking):
    """Speed the compensating wheel ``tg``'s filtered slip is taken against (signal_filter_flag): without the
    driver's brake the two intact wheels that are neither blown (b) nor braked by the compensation roll free, and the
    mean of their moving means is the car's speed without selection bias; the rate-bounded ``v_ref`` follows the
    highest wheel up at 2 m/s^2 but falls only at the 0.05 m/s^2 margin, so with noise it rides the upper edge of the
    noise (+2 sigma of the filtered wheels: +0.36 % slip at 60 km/h and 0.2 rad/s, 10 % of a 3.5 % rear cap). While
    the driver brakes every wheel slips: ``v_ref`` (the ABS reference)."""
    if braking > 0.5 or b < 0 or tg < 0:
        return v_ref
    acc = 0.0
    for i in range(4):
        if i != b and i != tg:
            acc += 0.5 * wheel_speed_mean(st, i)
    return acc


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_accel_mps2(st, i, dt, window=WS_WINDOW_N):
    """Wheel i's circumferential acceleration [m/s^2]: least-squares slope of its last ``window`` (at most WS_WINDOW_N)
    speed samples (first-derivative Savitzky-Golay filter of degree 1: Savitzky and Golay, Analytical Chemistry 36
    (1964) 1627), the derivative at the window centre, as ``wheel_speed_mean``; 0 with fewer than 2 samples. The ESP's
    ABS reads it too, over its shorter window (functions/esp.py ``abs_wheel_decel_mps2``)."""
    n = WS_WINDOW_N
    m = min(int(st[S_BUF_FILL]), window)
    if m < 2:
        return 0.0
    k = int(st[S_BUF_LAST])
    tbar = 0.5 * (m - 1)
    num = 0.0
    den = 0.0
    for j in range(m):
        tj = (m - 1 - j) - tbar  # sample j periods old at time index m - 1 - j
        num += tj * st[S_VW_BUF + i * n + (k - j) % n]
        den += tj * tj
    return num / (den * max(dt, 1e-6))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def dump_window_reading(st, i, p_now, dt):
    """(pressure [Pa], deceleration [m/s^2, > 0 = slowing]) of wheel i over the wheel-signal window, for the ABS dump
    reading (``abs_dump_noise_flag``; called by functions/esp.py at the dump's start, after ``reference_step`` pushed
    this period's speeds and BEFORE ``blowout_step`` pushes this period's pressures: ``p_now`` is the estimate of the
    last interval). The least-squares slope of m speed samples equals a weighted mean of the m - 1 one-period
    differences, sum_q w_q*(v_q - v_q+1)/dt with w_q = 6*(q + 1)*(m - 1 - q)/(m*(m^2 - 1)) > 0, sum w_q = 1 (summation
    by parts of the slope's coefficients (t_j - t_bar)/sum (t - t_bar)^2); each interval's pressure is the LOWER of the
    estimates at its two ends: under one valve state a wheel's pressure moves monotonically toward its source (filling /
    emptying through an orifice), so over the interval it is at least the lower end - and the estimate steps to the
    source pressure at once when the wheel goes back to W_N (functions/esp.py ``_estimate``) while the wheel still lags
    (tire_blowout_findings.md I1: a dump 5 ms after such a step, 167.8 bar estimated vs 53.6 bar in the wheel). The wheel's spin balance J*omega_dot = F_x*R - T_b holds in
    every interval, so with the same weights sum w_q*F_x,q*R = K_b*g*p_w - J*a_w/R: a weighted mean of the road force,
    and F_x <= mu*F_z at every instant makes it a lower bound of mu*F_z (tire_blowout.md 2.3) whatever the wheel did
    inside the window. Noise: white speed noise sigma_v per sample gives the slope the standard error
    sigma_v/sqrt(sum (t_j - t_bar)^2) = sigma_v/(dt*sqrt(m*(m^2 - 1)/12)) (ordinary least squares, Var(b) =
    sigma^2/S_tt; e.g. Montgomery, Peck and Vining, Introduction to Linear Regression Analysis, sec. 2.2): 0.154*sigma_v/dt
    at m = 8, 6.5 x less than the one-period difference and 4.6 x less than ABS's 3-sample slope. Before the window
    is full (the first WS_WINDOW_N - 1 periods of a run) no reading: (0, 0) - no force proven, no raise."""
    n = WS_WINDOW_N
    m = int(st[S_BUF_FILL])
    if m < n:
        return 0.0, 0.0
    k = int(st[S_BUF_LAST])
    norm = m * (m * m - 1) / 6.0
    p_w = 0.0
    a_w = 0.0
    for q in range(m - 1):  # interval q from time index q to q + 1 (time index q is m - 1 - q periods old)
        w = (q + 1) * (m - 1 - q) / norm
        j_old = m - 1 - q
        j_new = m - 2 - q
        v_old = st[S_VW_BUF + i * n + (k - j_old) % n]
        v_new = st[S_VW_BUF + i * n + (k - j_new) % n]
        a_w += w * (v_old - v_new) / max(dt, 1e-6)
        p_end = p_now if j_new == 0 else st[S_P_BUF + i * n + (k - j_new) % n]
        p_start = st[S_P_BUF + i * n + (k - j_old) % n]
        p_w += w * min(p_start, p_end)
    return p_w, a_w


@nb.njit(cache=True, nogil=True, error_model="numpy")
def dump_window_decel_sigma_mps2(p, dt):
    """1 sigma [m/s^2] of ``dump_window_reading``'s deceleration at the design wheel-speed noise
    (abs_dump_speed_noise_radps, white, per sample) over a full window: sigma_v/(dt*sqrt(N*(N^2 - 1)/12))."""
    n = WS_WINDOW_N
    sigma_v = p.blowout_compensation_abs_dump_speed_noise_radps * p.body_wheel_radius_m
    return sigma_v / (max(dt, 1e-6) * math.sqrt(n * (n * n - 1) / 12.0))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def intact_braking_force_n(slip, fz_n, mu, cx_n):
    """Retarding force of an intact wheel at braking slip s, alpha = 0 (spec 4, both H branches)."""
    if slip <= 0.0 or fz_n <= 0.0:
        return 0.0
    s = min(slip, 1.0)
    if s >= 1.0:
        return mu * fz_n
    h = mu * fz_n * (1.0 - s) / (2.0 * cx_n * s)
    if h >= 1.0:
        return cx_n * s / (1.0 - s)
    return mu * fz_n - (mu * fz_n) ** 2 * (1.0 - s) / (4.0 * cx_n * s)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def added_yaw_moment_nm(blown, fz_fl, fz_fr, fz_rl, fz_rr, slip, mu, mu_blow, cx_front_n, cx_rear_n, b_f, b_r):
    """M_z_blow [N*m] (eqs. 22-25) from redistributed loads F'_z; CCW + (a left blown wheel gives > 0)."""
    if blown < 0:
        return 0.0
    fz = (fz_fl, fz_fr, fz_rl, fz_rr)
    fb = np.zeros(4)
    for i in range(4):
        if i == blown:
            fb[i] = mu_blow * fz[i]
        else:
            fb[i] = intact_braking_force_n(slip, fz[i], mu, cx_front_n if i < 2 else cx_rear_n)
    return b_f * (fb[0] - fb[1]) + b_r * (fb[2] - fb[3])


@nb.njit(cache=True, nogil=True, error_model="numpy")
def required_pressure_pa(m_z_nm, wheel_radius_m, half_track_m, gain_nm_per_pa):
    """Eq. (28): p_w = |M_z_blow|*R_w/(b*K_b), K_b = A_p*r_b*mu_b*eta_b*n_f (eq. 26)."""
    return abs(m_z_nm) * wheel_radius_m / (half_track_m * gain_nm_per_pa)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def toward_blown_side(blown, value):
    """``value`` (a CCW + yaw rate or moment) signed so that + points toward the blown wheel's side."""
    return value * (1.0 if (blown == 0 or blown == 2) else -1.0)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def curve_toward_blown_side(blown, r_ref, p):
    """The driver steers a curve toward the blown wheel's side: the steered reference yaw rate ``r_ref`` points toward
    it by more than the yaw dead band (the gate of several rules: the inner front held, the inner rear not released)."""
    return toward_blown_side(blown, r_ref) > p.blowout_compensation_yaw_deadband_radps


@nb.njit(cache=True, nogil=True, error_model="numpy")
def valve_pressure_pa(t, p_max_pa, t0_s, t1_s, t2_s):
    """Eq. (29): wheel pressure t seconds after the inlet valve is energised (two linear segments)."""
    p1 = 0.45 * p_max_pa
    p2 = 0.9 * p_max_pa
    if t <= t0_s:
        return 0.0
    if t <= t1_s:
        return p1 * (t - t0_s) / (t1_s - t0_s)
    if t <= t2_s:
        return p1 + (p2 - p1) * (t - t1_s) / (t2_s - t1_s)
    return p2


@nb.njit(cache=True, nogil=True, error_model="numpy")
def valve_time_s(p_pa, p_max_pa, t0_s, t1_s, t2_s):
    """Eq. (30): (valve-opening time for pressure p, saturated flag); p > 0.9*p_max saturates at t2."""
    p1 = 0.45 * p_max_pa
    p2 = 0.9 * p_max_pa
    if p_pa <= 0.0:
        return 0.0, False
    if p_pa <= p1:
        return t0_s + (t1_s - t0_s) * p_pa / p1, False
    if p_pa <= p2:
        return t1_s + (t2_s - t1_s) * (p_pa - p1) / (p2 - p1), False
    return t2_s, True


@nb.njit(cache=True, nogil=True, error_model="numpy")
def linear_slip_limit_frac(mu, fz_n, fy_n, cx_n):
    """Largest braking slip at which braking does not yet take lateral force away from the wheel, derived from the
    Dugoff tire (spec 2.3), for a wheel carrying the (linear) lateral force ``fy_n``: F_y = C_y*tan(alpha)/(1 - s)*f(H)
    keeps at least its unbraked value C_y*tan(alpha) while f(H) >= 1 - s, with the linear forces F_x,l = C_x*s/(1 - s),
    F_y,l = ``fy_n`` and H = mu*F_z/(2*sqrt(F_x,l^2 + F_y,l^2)). Inside the linear region (H >= 1, f = 1) it always
    holds; beyond it f(H) = H*(2 - H) falls: bisection for f(H) = 1 - s from the H = 1 slip (closed form at fy = 0:
    s* = (2k + k^2 + k*sqrt(k^2 + 4k))/2, k = mu*F_z/(2*C_x)). 0 when the lateral force alone uses mu*F_z/2."""
    if fz_n <= 0.0 or mu <= 0.0:
        return 0.0
    half = 0.5 * mu * fz_n
    if fy_n * fy_n >= half * half:
        return 0.0
    fx_l = math.sqrt(half * half - fy_n * fy_n)
    lo = fx_l / (cx_n + fx_l)
    hi = 0.5
    for _ in range(60):
        sm = 0.5 * (lo + hi)
        fxm = cx_n * sm / (1.0 - sm)
        h = half / math.sqrt(fxm * fxm + fy_n * fy_n)
        fh = 1.0 if h >= 1.0 else h * (2.0 - h)
        if fh >= 1.0 - sm:
            lo = sm
        else:
            hi = sm
    return lo


@nb.njit(cache=True, nogil=True, error_model="numpy")
def rear_linear_limit(target, fz_straight_n, a_y, p):
    """``rear_linear_limit_mu`` at the ECU's nominal friction mu_estimate_frac."""
    return rear_linear_limit_mu(target, fz_straight_n, a_y, p.blowout_compensation_mu_estimate_frac, p)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def rear_linear_limit_mu(target, fz_straight_n, a_y, mu, p):
    """(brake force [N], slip) up to which the rear compensating wheel ``target`` stays in the Dugoff linear
    region while carrying the rear axle's lateral force, from the ECU's nominal data: a_y = u*r_ref(delta), the
    lateral acceleration the measured steer angle asks for (reference_yaw_rate; the curve's, or the driver's
    counter-steer: driver and brake then do not correct twice; the blowout's own yaw, which the compensation
    removes, does not count - with the measured u*omega_r a rear blowout at 120 km/h lost its compensation), the
    wheel's load = its straight-driving load (blowout transfer included) -+ the rear lateral load transfer
    m*a_y*h*l_f/(B_r*l) (spec eqs. 3-4), the axle's lateral force m*|a_y|*l_f/l shared with the flat tire by
    cornering stiffness (below), then the Dugoff H = 1 boundary (linear_slip_limit_frac)."""
    return wheel_linear_limit_mu(target, fz_straight_n, a_y, mu, OPPOSITE[target], p)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_load_and_lateral_n(i, fz_straight_n, a_y, blown, p):
    """(F_z [N], F_y [N]) of intact wheel ``i`` in a steady turn at a_y: its straight-driving load -+ the axle's lateral
    load transfer m*a_y*h*l_o/(B*l) (spec eqs. 3-4, l_o = the other axle's distance to the CG) and its share of the
    axle's lateral force m*|a_y|*l_o/l, shared by cornering stiffness with the other wheel of the axle (the flat tire
    ``blown`` k_Cy*C_y, an intact one C_y)."""
    l = p.chassis_wheelbase_m
    l_f = p.chassis_cg_to_front_axle_m
    m = p.body_mass_kg
    front = i < 2
    l_o = (l - l_f) if front else l_f
    track = p.chassis_front_track_m if front else p.chassis_rear_track_m
    d_fz = m * a_y * p.chassis_cg_height_m * l_o / (track * l)
    fz = fz_straight_n + (-d_fz if i % 2 == 0 else d_fz)  # a_y > 0 (left turn) loads the right wheels
    other = i + 1 if i % 2 == 0 else i - 1
    k_other = p.blowout_cornering_stiffness_frac if other == blown else 1.0
    fy = m * abs(a_y) * l_o / l / (1.0 + k_other)
    return fz, fy


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_linear_limit_mu(i, fz_straight_n, a_y, mu, blown, p):
    """(brake force [N], slip) up to which intact wheel ``i`` (front or rear) stays in the Dugoff linear region while
    carrying its share of its axle's lateral force for a_y (``braking_rule``; ``rear_linear_limit_mu`` for any wheel):
    load = its straight-driving load -+ the axle's lateral load transfer m*a_y*h*l_o/(B*l) (spec eqs. 3-4, l_o = the
    other axle's distance to the CG), axle lateral force m*|a_y|*l_o/l shared by cornering stiffness with the other
    wheel of the axle (the flat tire ``blown`` k_Cy*C_y, an intact one C_y), then the f(H) >= 1 - s boundary
    (``linear_slip_limit_frac``)."""
    fz, fy = wheel_load_and_lateral_n(i, fz_straight_n, a_y, blown, p)
    cx = p.tires_longitudinal_stiffness_n
    s_lin = linear_slip_limit_frac(mu, fz, fy, cx)
    fx_l = cx * s_lin / (1.0 - s_lin)
    if fx_l <= 0.0:
        return 0.0, s_lin
    h = 0.5 * mu * fz / math.sqrt(fx_l * fx_l + fy * fy)
    return fx_l * (1.0 if h >= 1.0 else h * (2.0 - h)), s_lin


@nb.njit(cache=True, nogil=True, error_model="numpy")
def tire_capacity_check(p_wheel_pa, vw_now, vw_prev, v_ref, dt, gain_nm_per_pa, p):
    """Force-slip estimate of one braked wheel from measurements only (derived: the Dugoff saturation of spec 2.3
    inverted, cf. the Dugoff fit of Villagra et al., Control Engineering Practice 19 (2011)): brake force
    F_x = (K_b*p + J*d(omega)/dt)/R (wheel spin balance J*omega_dot = F_x*R - T_b, T_b = K_b*p the ECU's nominal brake
    gain on its pressure estimate), slip s = (v_ref - omega*R)/v_ref, and the ratio q = F_x/(C_x*s/(1 - s)) to the
    nominal linear force: Dugoff gives q = f(H) (1 in the linear region, H*(2 - H) below it, spec 2.3). Returns
    (F_x [N], s, q, friction capacity mu*F_z [N]); the capacity inverts f: H = 1 - sqrt(1 - q), mu*F_z =
    2*H*C_x*s/(1 - s) (alpha = 0 form; with a lateral force it under-states the capacity: conservative)."""
    r_w = p.body_wheel_radius_m
    omega_dot = (vw_now - vw_prev) / (r_w * max(dt, 1e-6))
    return tire_capacity_estimate(p_wheel_pa, vw_now, omega_dot, v_ref, gain_nm_per_pa, p)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def tire_capacity_estimate(p_wheel_pa, vw_now, omega_dot, v_ref, gain_nm_per_pa, p):
    """``tire_capacity_check`` with the wheel's angular acceleration given (raw difference or the filtered slope)."""
    r_w = p.body_wheel_radius_m
    fx = (gain_nm_per_pa * max(p_wheel_pa, 0.0) + p.body_wheel_inertia_kgm2 * omega_dot) / r_w
    s = min(max((v_ref - vw_now) / max(v_ref, 1.0), 0.0), 0.99)
    lin = p.tires_longitudinal_stiffness_n * s / (1.0 - s)
    if lin <= 0.0:
        return fx, s, 1.0, 0.0
    q = min(max(fx / lin, 0.0), 1.0)
    h = 1.0 - math.sqrt(1.0 - q)
    return fx, s, q, 2.0 * h * lin


@nb.njit(cache=True, nogil=True, error_model="numpy")
def ecu_loads(p, a_x):
    """The ECU's static + longitudinal-transfer wheel loads from its nominal data (straight driving)."""
    m = p.body_mass_kg
    g = G_MPS2
    l = p.chassis_wheelbase_m
    l_f = p.chassis_cg_to_front_axle_m
    l_r = l - l_f
    h = p.chassis_cg_height_m
    front = 0.5 * m * (g * l_r - a_x * h) / l
    rear = 0.5 * m * (g * l_f + a_x * h) / l
    return front, front, rear, rear



@nb.njit(cache=True, nogil=True, error_model="numpy")
def blown_ecu_loads(b, a_x, p):
    """The ECU's wheel loads [N] with wheel ``b`` blown: ``ecu_loads`` at a_x, then the flat's radius loss
    redistributed over the suspension (eqs. 3-4, ``transfer_n`` / ``redistributed_loads``)."""
    f0, f1, f2, f3 = ecu_loads(p, a_x)
    d_r = p.body_wheel_radius_m - p.blowout_inner_radius_m
    f = transfer_n(b, f0, f1, f2, f3, d_r, p.blowout_suspension_rate_front_n_per_m,
                   p.blowout_suspension_rate_rear_n_per_m)
    return redistributed_loads(b, f0, f1, f2, f3, f)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def reference_yaw_rate(steer_rad, speed_mps, p):
    """The ECU's expected yaw rate for the measured road-wheel angle (linear single-track steady state,
    r = u*delta/(l + K*u^2), K = m/l*(l_r/C_f - l_f/C_r) from its nominal data; standard ESP practice):
    yaw is judged as the deviation from it, so a curve's own yaw rate is not taken for a blowout's."""
    l_f = p.chassis_cg_to_front_axle_m
    l = p.chassis_wheelbase_m
    k = p.body_mass_kg / l * ((l - l_f) / (2.0 * p.tires_cornering_stiffness_front_n_per_rad)
                              - l_f / (2.0 * p.tires_cornering_stiffness_rear_n_per_rad))
    return speed_mps * steer_rad / (l + k * speed_mps * speed_mps)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def released_moment_nm(b, tg, braking, p_est, p_add_cmd_pa, p):
    """Yaw moment [N*m, + = away from the blown side] of the function's own release of the blown wheel ``b`` from the
    braking driver's pressure (``yaw_net_flag``): b*K_b*dp/R on the blown axle, dp = the driver's share of the same-axle
    opposite wheel's pressure estimate (the estimate less the compensation pressure ``p_add_cmd_pa`` commanded on top
    of it when that wheel is the target) minus what the blown wheel still carries. The opposite wheel's estimate is the
    measured master pressure as the ESP (proportioning, ABS) lets it through, i.e. what the blown wheel would carry
    without the function. Zero without the brake-light switch (nothing of the driver's to release)."""
    if b < 0 or braking < 0.5:
        return 0.0
    o = OPPOSITE[b]
    p_drv = p_est[o] - (max(p_add_cmd_pa, 0.0) if tg == o else 0.0)
    dp = max(p_drv - max(p_est[b], 0.0), 0.0)
    if b < 2:
        return 0.5 * p.chassis_front_track_m * p.brakes_front_gain_nm_per_pa * dp / p.body_wheel_radius_m
    return 0.5 * p.chassis_rear_track_m * p.brakes_rear_gain_nm_per_pa * dp / p.body_wheel_radius_m


@nb.njit(cache=True, nogil=True, error_model="numpy")
def released_moment_bound_nm(b, a_x, p):
    """Lower bound [N*m] of the release's yaw moment while the same-axle braked wheel is past its linear region
    (``release_bound_flag``): a saturated tire carries mu*F_z (friction circle, spec 2.3), and the road friction is at
    least the car's mean utilisation |a_x|/g (the braking forces sum to m*|a_x| <= mu*m*g), so that wheel's force is at
    least |a_x|/g*F_z (ECU nominal load, ``ecu_loads``); the released flat wheel carries ~0."""
    o = OPPOSITE[b]
    f0, f1, f2, f3 = ecu_loads(p, a_x)
    m = p.body_mass_kg
    decel_n = m * abs(a_x)
    if p.blowout_compensation_release_bound_drag_flag > 0.5:
        # (release_bound_drag_flag, 0 = seeded defect: |a_x|/g alone) the measured deceleration also holds the flat
        # wheel's own drag, which is not the road friction the braked tires use: the ECU's drag of eqs. 22-25 (the
        # plan's mu_blow*F'_z on the redistributed load, _plan) comes off before the friction bound. Without it the
        # bound took |a_x|/g 0.63-0.75 for mu 0.58-0.59 (falsifier braking points, review r1)
        g = blown_ecu_loads(b, a_x, p)
        drag = p.blowout_compensation_mu_estimate_frac * p.blowout_compensation_blow_drag_frac * g[b]
        decel_n = max(decel_n - drag, 0.0)
    f_o = decel_n / (m * G_MPS2) * (f0, f1, f2, f3)[o]
    track = p.chassis_front_track_m if b < 2 else p.chassis_rear_track_m
    return 0.5 * track * f_o


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _opposite_linear(st, b, v_ref, a_x, p):
    """Validity of the single-track model of the released moment (``yaw_net_flag``): the same-axle wheel that carries
    the driver's brake force is inside its tire's linear region - its filtered slip (window mean against v_ref) at or
    below ``linear_slip_limit_frac`` at the ECU's nominal mu, its nominal load (``ecu_loads``) and no lateral force.
    Beyond it the braked tire saturates and loses lateral force (a braking driver after a front blowout: the opposite
    front at 8-10 % slip on mu 0.35, the car runs wide, issue #10 open item 2): the yaw is then not the model's, and the
    raw yaw decides (rejecting gave 0.75 m there, the net yaw 4.35 m, none 2.98 m)."""
    o = OPPOSITE[b]
    loads = ecu_loads(p, a_x)
    cap = linear_slip_limit_frac(p.blowout_compensation_mu_estimate_frac, loads[o], 0.0,
                                 p.tires_longitudinal_stiffness_n)
    slip = (v_ref - wheel_speed_mean(st, o)) / max(v_ref, 1.0)
    return slip <= cap


@nb.njit(cache=True, nogil=True, error_model="numpy")
def own_yaw_step(st, m_z_nm, speed_mps, dt, p):
    """One ESP period of the ECU's linear single-track model (nominal data, steer 0, as ``reference_yaw_rate``) driven
    by the yaw moment ``m_z_nm`` [CCW +] (explicit Euler; states S_BETA_OWN, S_R_OWN):
    m*u*(beta_dot + r) = -(C_f + C_r)*beta - (C_f*l_f - C_r*l_r)*r/u,
    I_z*r_dot = -(C_f*l_f - C_r*l_r)*beta - (C_f*l_f^2 + C_r*l_r^2)*r/u + M_z;
    steady state r/M_z = u*(C_f + C_r)/(C_f*C_r*l*(l + K*u^2)). Returns the model yaw rate [rad/s, CCW +]."""
    u = max(speed_mps, 1.0)
    l_f = p.chassis_cg_to_front_axle_m
    l_r = p.chassis_wheelbase_m - l_f
    c_f = 2.0 * p.tires_cornering_stiffness_front_n_per_rad
    c_r = 2.0 * p.tires_cornering_stiffness_rear_n_per_rad
    m = p.body_mass_kg
    beta = st[S_BETA_OWN]
    r = st[S_R_OWN]
    d = c_f * l_f - c_r * l_r
    beta_dot = (-(c_f + c_r) * beta - d * r / u) / (m * u) - r
    r_dot = (-d * beta - (c_f * l_f * l_f + c_r * l_r * l_r) * r / u + m_z_nm) / p.body_yaw_inertia_kgm2
    st[S_BETA_OWN] = beta + beta_dot * dt
    st[S_R_OWN] = r + r_dot * dt
    return st[S_R_OWN]


@nb.njit(cache=True, nogil=True, error_model="numpy")
def released_wheel_healthy(st, b, v_ref, a_x, p_est, dt, p):
    """TPMS-path confirmation (``tpms_confirm_flag``, 0 = seeded defect = no confirmation): a TPMS-only detection made
    while the driver brakes releases the named wheel b. A flat wheel, once free of the brake, is driven up by its road
    force toward its own free-rolling speed, (R_out/R_in - 1) ~ 50 % above the car's: it over-speeds (the wheel-speed
    signature, threshold wheel_speed_threshold_frac) or at least spins up faster than the car decelerates. A healthy
    wheel rolls at the car's speed and decelerates with it. Returns True (not confirmed: a false TPMS alarm) once b's
    filtered speed has stayed within the threshold band around v_ref with its filtered acceleration at most
    a_x + SPINUP_MARGIN_MPS2, with its pressure estimate down to the release level (free of the brake), for
    HEALTHY_PERSIST_S; over-speed above the band confirms the detection for good
    (S_HEALTHY_S = -1, no further check)."""
    thr = p.blowout_compensation_wheel_speed_threshold_frac
    v_b = wheel_speed_mean(st, b)
    if v_b > v_ref * (1.0 + thr):
        st[S_HEALTHY_S] = -1.0  # the blowout's over-speed: confirmed
        return False
    free = p_est[b] <= p.esp_unit_lpa_pressure_pa + RELEASED_MARGIN_PA
    if free and abs(v_b - v_ref) <= thr * v_ref and wheel_accel_mps2(st, b, dt) <= a_x + SPINUP_MARGIN_MPS2:
        st[S_HEALTHY_S] += dt
    else:
        st[S_HEALTHY_S] = 0.0
    return st[S_HEALTHY_S] >= HEALTHY_PERSIST_S - 1e-9


@nb.njit(cache=True, nogil=True, error_model="numpy")
def stability_bounds(mu, speed_mps):
    """(yaw-rate bound [rad/s], sideslip bound [rad]) of the stable region (Rajamani, Vehicle Dynamics and Control,
    2nd ed. 2012, ch. 8 yaw control - the bounds widely used in ESP literature): |r| <= 0.85*mu*g/u (the yaw rate
    the road friction can carry: u*r <= mu*g, 15 % margin), |beta| <= atan(0.02*mu*g)."""
    g = G_MPS2
    return YAW_BOUND_FRAC * mu * g / max(speed_mps, 1.0), math.atan(SIDESLIP_BOUND_S2_PER_M * mu * g)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def unstable_code(yaw_rate_meas, beta_est, speed_mps, p):
    """Refusal code (LIMIT_YAW_BOUND / LIMIT_SIDESLIP_BOUND, LIMIT_NONE inside) of the measured yaw rate and the
    kinematic sideslip estimate against ``stability_bounds`` at the ECU's nominal friction mu_estimate_frac: the
    highest friction the ECU assumes (tire_blowout.md 7, cement road 0.8), so the bounds are the loosest of the
    envelope's roads and a refusal means beyond the stable region even on the best road. (The measured |a_y|/g is
    only the friction in use, a lower bound of the road's: with it every steady curve, u*r = a_y, would exceed
    0.85*a_y/u.)"""
    if p.blowout_compensation_stability_refusal_flag < 0.5:
        return LIMIT_NONE
    r_max, beta_max = stability_bounds(p.blowout_compensation_mu_estimate_frac, speed_mps)
    if abs(yaw_rate_meas) > r_max:
        return LIMIT_YAW_BOUND
    if abs(beta_est) > beta_max:
        return LIMIT_SIDESLIP_BOUND
    return LIMIT_NONE


@nb.njit(cache=True, nogil=True, error_model="numpy")
def phase_plane_unstable(beta_est, beta_dot, p):
    """``phase_plane_flag`` (0 = seeded defect = the mu-0.8 bounds of ``unstable_code`` alone): True when the sideslip /
    sideslip-rate state lies outside the stable region of the beta-beta_dot phase plane, |beta_dot + B1*beta| > B2
    (Inagaki, Kushiro, Yamamoto, AVEC 1994 / JSAE Review 16 (1995): critical cornering by the phase-plane method;
    B1 = phase_plane_b1, B2 = phase_plane_b2, the dry-road boundary). Friction-free and from measurements only:
    beta_dot = a_y/u - r (kinematic, the measured lateral acceleration against the yaw rate it would need, u*r) and beta
    its integral from the detection (S_BETA_EST). The dry-road boundary is the loosest (a lower friction shrinks the
    stable region), as the nominal mu 0.8 of ``unstable_code`` is the loosest of the envelope's roads; unlike the yaw
    bound it is crossed as soon as the rear slides (the sideslip grows) on any friction - on mu 0.48 the yaw-rate bound
    0.85*0.8*g/u is reached only once the car has turned through its slide (random 7 #7: 3.39 s vs 2.36 s)."""
    if p.blowout_compensation_phase_plane_flag < 0.5:
        return False
    return abs(beta_dot + p.blowout_compensation_phase_plane_b1_per_s * beta_est) > p.blowout_compensation_phase_plane_b2_radps


@nb.njit(cache=True, nogil=True, error_model="numpy")
def excluded_wheel(st):
    """Wheel the reference speed ignores: the detected blown wheel, else the one the TPMS named (-1 none)."""
    return int(st[S_EXCLUDED])


@nb.njit(cache=True, nogil=True, error_model="numpy")
def reference_step(st, vw, a_x, tpms_wheel, dt, p):
    """Rate-bounded reference speed from the wheels not known/suspected blown (module doc); returns it."""
    ex = int(st[S_BLOWN])
    if ex < 0 and p.blowout_compensation_enabled_flag > 0.5:
        ex = int(tpms_wheel + 0.5) - 1
    st[S_EXCLUDED] = ex if p.blowout_compensation_enabled_flag > 0.5 else -1.0
    _push_wheels(st, vw)
    filt = p.blowout_compensation_signal_filter_flag > 0.5
    v_max = 0.0
    for i in range(4):
        if i != ex:
            # filtered (signal_filter_flag): the max of raw noisy wheels, rate-bounded up at 2 m/s^2 but down only at
            # the 0.05 m/s^2 margin, ratchets to the upper edge of the noise (+0.2 m/s, 1.2 % slip at 60 km/h and
            # 0.2 rad/s); the max of the wheels' moving means is the filtered selection of EP 0348072 (Lucas, ABS
            # reference speed: wheel-speed selection, slew-rate limit, filter)
            v_max = max(v_max, wheel_speed_mean(st, i) if filt else vw[i])
    if filt:
        # the moving mean is the speed at the window centre, (m - 1)/2 periods old: carried to now with the measured
        # a_x (without it the panic stop's reference lagged 0.14 m/s at 8 m/s^2 and ABS was released at 3.6 km/h)
        v_max += a_x * 0.5 * (st[S_BUF_FILL] - 1.0) * dt
    if st[S_STARTED] < 0.5:
        st[S_STARTED] = 1.0
        st[S_VREF] = v_max
        return v_max
    lo = st[S_VREF] - (abs(min(a_x, 0.0)) + p.esp_reference_decel_margin_mps2) * dt
    hi = st[S_VREF] + (max(a_x, 0.0) + RISE_MARGIN_MPS2) * dt
    st[S_VREF] = min(max(v_max, lo), hi)
    return st[S_VREF]


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _candidate_ws(vw, v_ref, thr, skip):
    """Wheel-speed blowout signature: the wheel faster than max(v_ref, median of the others) by thr (-1 none)."""
    cand = -1
    best = 0.0
    for i in range(4):
        if i == skip:
            continue
        others = np.zeros(3)
        k = 0
        for j in range(4):
            if j != i:
                others[k] = vw[j]
                k += 1
        base = max(np.median(others), v_ref)
        if base > 0.0 and vw[i] > base * (1.0 + thr) and vw[i] / base > best:
            best = vw[i] / base
            cand = i
    return cand


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _substitute(b):
    """Intact wheel of the other axle on the side of the opposite wheel (LIMITED)."""
    o = OPPOSITE[b]
    return o + 2 if o < 2 else o - 2


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _release_unconfirmed_latch(st):
    """A refusal of a detection from ONE source (wheel speed or TPMS, not both): the wheel is not confirmed flat, so it
    is no longer held released - ABS/HBA treat it as without the function (independent review of issue #10: a
    refused false TPMS alarm kept a healthy wheel released for good; the REJECTED path already cleared it)."""
    if st[S_SOURCES] < SRC_WS + SRC_TPMS - 0.5:
        st[S_BLOWN] = -1.0
        st[S_EXCLUDED] = -1.0
        st[S_SUSPECT] = -1.0
        st[S_SUSPECT_S] = 0.0


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _plan(st, b, target, limited, slip_mean, a_x, a_y, p_est, p):
    """Estimate (eqs. 13-25), added pressure (eq. 28) on top of the target's present pressure, valve time
    (eq. 30) for blown wheel b braking ``target``; capped at the lock estimate when ``limited``."""
    g0, g1, g2, g3 = blown_ecu_loads(b, a_x, p)
    s_est = min(max(slip_mean, 0.0), 1.0)
    st[S_SLIP_EST] = s_est
    b_f = 0.5 * p.chassis_front_track_m
    b_r = 0.5 * p.chassis_rear_track_m
    mu = p.blowout_compensation_mu_estimate_frac
    m_z = added_yaw_moment_nm(b, g0, g1, g2, g3, s_est, mu, mu * p.blowout_compensation_blow_drag_frac,
                              p.tires_longitudinal_stiffness_n, p.tires_longitudinal_stiffness_n, b_f, b_r)
    st[S_M_EST] = m_z
    st[S_TARGET] = target
    half = b_f if target < 2 else b_r
    gain = p.brakes_front_gain_nm_per_pa if target < 2 else p.brakes_rear_gain_nm_per_pa
    # a moment already pointing away from the blown side (intact wheels braked hard) needs no opposite braking
    p_add = required_pressure_pa(m_z, p.body_wheel_radius_m, half, gain) if toward_blown_side(b, m_z) > 0.0 else 0.0
    p0 = max(p_est[target], 0.0)
    gl = (g0, g1, g2, g3)
    st[S_FZ_TARGET] = gl[target]
    st[S_SLIP_LIMITED] = 0.0  # a new plan (new wheel or substitute) starts unlimited
    st[S_CAP_LATCHED] = 0.0  # ... and with its own tire-capacity check (tire_capacity_rule)
    st[S_LOW_S] = 0.0
    st[S_F_CAP] = 0.0
    st[S_VW_PREV] = -1.0
    st[S_SLIP_HIGH_S] = 0.0
    st[S_US_LIMITED] = 0.0  # ... and not lowered by the understeer rule (understeer_rule)
    if p.blowout_compensation_measured_mu_bound_flag > 0.5:
        st[S_LIN_S] = 0.0  # ... and a new wheel's linear-reading time starts from zero (measured_mu_raise)
    if target >= 2 and p.blowout_compensation_slip_limit_flag > 0.5:
        # rear compensating wheel: its brake force kept inside the Dugoff linear region with the lateral force the
        # rear axle needs now (rear_linear_limit); the feed-forward pressure is capped at that force
        fx_lin, s_lin = rear_linear_limit(target, gl[target], a_y, p)
        st[S_SLIP_CAP] = s_lin
        p_add = max(min(p_add, fx_lin * p.body_wheel_radius_m / gain - p0), 0.0)
    if limited:
        p_lock = mu * gl[target] * p.body_wheel_radius_m / gain
        p_add = max(min(p_add, p_lock - p0), 0.0)
    p_max = p.esp_unit_accumulator_pa
    t_end, sat = valve_time_s(p0 + p_add, p_max, p.blowout_compensation_valve_dead_time_s,
                              p.blowout_compensation_valve_t1_s, p.blowout_compensation_valve_t2_s)
    t_beg, _ = valve_time_s(p0, p_max, p.blowout_compensation_valve_dead_time_s,
                            p.blowout_compensation_valve_t1_s, p.blowout_compensation_valve_t2_s)
    dead = p.blowout_compensation_valve_dead_time_s if p0 > 0.0 else 0.0  # the dead time t0 is paid once
    st[S_P_ADD] = p_add
    st[S_P_START] = p0
    st[S_P_REQ] = p0 + p_add
    st[S_T_VALVE] = max(t_end - t_beg + dead, 0.0) if p_add > 0.0 else 0.0
    st[S_SATURATED] = 1.0 if sat else 0.0
    st[S_ELAPSED] = 0.0


@nb.njit(cache=True, nogil=True, error_model="numpy")
def spin_front_applies(b, tg, yaw_rate_meas, code, beta_est, beta_dot, inlet_ok, p):
    """``spin_front_flag`` (0 = seeded defect = refuse): a REAR blown wheel compensated on the rear axle, the measured
    yaw rate toward the blown side (the spin the flat rear tire starts) and the front wheel of the compensating side
    healthy. A trigger from the sideslip (``code`` = LIMIT_SIDESLIP_BOUND, or the phase plane) must also be the slide
    of that spin: in a spin toward the blown side the heading turns past the velocity, so beta and beta_dot + B1*beta
    point away from the blown side; pointing toward it they are the slide of the opposite rotation (the nose already
    right of the path for a left-blown wheel), which braking this front wheel would deepen (independent review V:
    RL, 60 km/h, r = 0.01 rad/s CCW, a_y = +5 m/s^2 moved the brake to FR at once; tests/functions/
    test_blowout_spin_front_sign.py)."""
    if p.blowout_compensation_spin_front_flag < 0.5 or b < 2 or tg < 2:
        return False
    if not (toward_blown_side(b, yaw_rate_meas) > 0.0 and inlet_ok[_substitute(b)] > 0.5):
        return False
    if code == LIMIT_YAW_BOUND:
        return True
    if code == LIMIT_SIDESLIP_BOUND and toward_blown_side(b, beta_est) < 0.0:
        return True
    return phase_plane_spin(b, yaw_rate_meas, beta_est, beta_dot, p)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def phase_plane_spin(b, yaw_rate_meas, beta_est, beta_dot, p):
    """The spin toward the blown side in the sideslip phase plane (Inagaki et al. 1994, ``phase_plane_unstable``): the
    state outside the stable region, the yaw rate toward the blown side, and beta_dot + B1*beta pointing away from it
    (the slide of that spin, not of the opposite rotation - see ``spin_front_applies``). The trigger of the spin-front
    rule and of the braking rule's rear oversteer cap (``rear_oversteer_cap``)."""
    return (toward_blown_side(b, yaw_rate_meas) > 0.0 and phase_plane_unstable(beta_est, beta_dot, p)
            and toward_blown_side(b, beta_dot + p.blowout_compensation_phase_plane_b1_per_s * beta_est) < 0.0)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _plan_spin_front(st, sub, p_est, p):
    """Spin-front target (after ``_plan`` on the front wheel ``sub``): the ECU's lock estimate mu*F'_z*R/K_b (nominal
    mu, redistributed load) - the outer front wheel braked up to its slip limit, ABS guarding it, as an ESP's oversteer
    intervention; valve time (eq. 30) for the build from its present pressure."""
    gain = p.brakes_front_gain_nm_per_pa
    p0 = max(p_est[sub], 0.0)
    p_lock = p.blowout_compensation_mu_estimate_frac * st[S_FZ_TARGET] * p.body_wheel_radius_m / gain
    p_add = max(p_lock - p0, 0.0)
    p_max = p.esp_unit_accumulator_pa
    t_end, sat = valve_time_s(p0 + p_add, p_max, p.blowout_compensation_valve_dead_time_s,
                              p.blowout_compensation_valve_t1_s, p.blowout_compensation_valve_t2_s)
    t_beg, _ = valve_time_s(p0, p_max, p.blowout_compensation_valve_dead_time_s,
                            p.blowout_compensation_valve_t1_s, p.blowout_compensation_valve_t2_s)
    dead = p.blowout_compensation_valve_dead_time_s if p0 > 0.0 else 0.0
    st[S_P_ADD] = p_add
    st[S_P_START] = p0
    st[S_P_REQ] = p0 + p_add
    st[S_T_VALVE] = max(t_end - t_beg + dead, 0.0) if p_add > 0.0 else 0.0
    st[S_SATURATED] = 1.0 if sat else 0.0
    st[S_ELAPSED] = 0.0
    st[S_SPIN_OK_S] = 0.0


@nb.njit(cache=True, nogil=True, error_model="numpy")
def settling_time_s(speed_mps, p):
    """2 % settling time 4/(zeta*omega_n) of the yaw/sideslip mode of the ECU's linear single-track model (nominal data,
    as ``own_yaw_step``): characteristic polynomial s^2 + a_1*s + a_0 with a_1 = (C_f + C_r)/(m*u) +
    (C_f*l_f^2 + C_r*l_r^2)/(I_z*u) = 2*zeta*omega_n (Rajamani 2012 ch. 2; 4/(zeta*omega_n): Ogata, Modern Control
    Engineering, 2 % criterion), so t_s = 8/a_1 - BJ2500 0.50 / 0.84 / 1.00 s at 60 / 100 / 120 km/h."""
    u = max(speed_mps, 1.0)
    l_f = p.chassis_cg_to_front_axle_m
    l_r = p.chassis_wheelbase_m - l_f
    c_f = 2.0 * p.tires_cornering_stiffness_front_n_per_rad
    c_r = 2.0 * p.tires_cornering_stiffness_rear_n_per_rad
    a_1 = (c_f + c_r) / (p.body_mass_kg * u) + (c_f * l_f * l_f + c_r * l_r * l_r) / (p.body_yaw_inertia_kgm2 * u)
    return 8.0 / a_1


@nb.njit(cache=True, nogil=True, error_model="numpy")
def spin_stopped(st, b, yaw_rate, code, beta_dot, speed_mps, inlet_ok, dt, p):
    """``spin_exit_flag`` (0 = seeded defect = no exit: the spin-front wheel braked to the end of the run; open item 5 of
    session 2026-11-24 e): while the spin-front wheel is braked (LIMITED, code 5), True once the car has stayed back
    inside the stable region for the settling time of the ECU's single-track yaw mode (``settling_time_s``) - inside
    the refusal's mu-0.8 yaw-rate and sideslip bounds (``code`` = LIMIT_NONE), inside the sideslip phase plane
    |beta_dot + B1*beta| <= B2 (``phase_plane_unstable``, Inagaki et al. 1994), the yaw rate relative to the steered
    reference (``yaw_rate``) not toward the blown side beyond the closed-loop dead band (the oversteer is over: an ESP
    ends its oversteer intervention with the yaw deviation back in its dead band, Bosch Automotive Handbook, ESP) - and
    the yaw angle the spin turned the car toward the blown side, the integral of that deviation from the detection
    (S_PSI_ERR), taken back (<= 0). The dead band and the heading are the hysteresis against the entry (the bounds /
    the phase-plane boundary themselves); the settling time keeps a swing of the yaw oscillation through the region
    from counting (exits after 0.1-0.5 s re-spun the car at the swing-back). The opposite rear wheel's inlet must be
    healthy."""
    if p.blowout_compensation_spin_exit_flag < 0.5 or inlet_ok[OPPOSITE[b]] < 0.5:
        st[S_SPIN_OK_S] = 0.0
        return False
    inside = (code == LIMIT_NONE and not phase_plane_unstable(st[S_BETA_EST], beta_dot, p)
              and toward_blown_side(b, yaw_rate) <= p.blowout_compensation_yaw_deadband_radps
              and st[S_PSI_ERR] <= 0.0)
    st[S_SPIN_OK_S] = st[S_SPIN_OK_S] + dt if inside else 0.0
    return st[S_SPIN_OK_S] >= settling_time_s(speed_mps, p) - 1e-9


@nb.njit(cache=True, nogil=True, error_model="numpy")
def blowout_step(st, vw, v_ref, braking, a_x, yaw_rate_meas, steer_rad, tpms_wheel, inlet_ok, p_est, p, dt, t,
                 machine_id, events, n_events, requests, a_y_meas=0.0, p_mc=0.0):
    """One ESP period of the compensation (after ``reference_step``); fills ``requests[4]`` (Q_*);
    ``braking`` = brake-light switch; ``p_est`` = the ECU's wheel-pressure estimates; the yaw rate is judged
    relative to ``reference_yaw_rate`` of the measured steer angle; ``a_y_meas`` = measured lateral acceleration
    (kinematic sideslip estimate beta_dot = a_y/u - r, integrated from the detection); returns n_events."""
    for i in range(4):
        requests[i] = Q_NONE
    _push_pressures(st, p_est)
    if p.blowout_compensation_enabled_flag < 0.5:
        return n_events
    if (p.blowout_compensation_blown_side_fault_flag > 2.5 or p.blowout_compensation_diagonal_fault_flag > 0.5
            or p.blowout_compensation_blown_side_single_flag > 0.5):
        for i in range(4):
            if inlet_ok[i] < 0.5 and st[S_L6_TRAPPED + i] < 0.0:
                st[S_L6_TRAPPED + i] = st[S_P_LINE + i]  # (blown_side_fault_flag 3) the pressure the fault trapped
    r_ref = reference_yaw_rate(steer_rad, v_ref, p)
    yaw_rate = yaw_rate_meas - r_ref
    a_y_ref = v_ref * r_ref  # lateral acceleration the driver's steering asks for (rear_linear_limit)
    mode = int(st[S_MODE])
    rejected = int(st[S_REJECTED])
    # detection: wheel-speed signature and/or TPMS alarm (index 1..4; 0 none)
    cand_ws = -1
    still = False  # the rejected wheel still shows its signature
    if v_ref > p.blowout_compensation_min_speed_mps:
        thr = p.blowout_compensation_wheel_speed_threshold_frac
        cand_ws = _candidate_ws(vw, v_ref, thr, rejected if mode == REJECTED else -1)
        if mode == REJECTED:
            still = _candidate_ws(vw, v_ref, thr, -1) == rejected
    cand_tp = int(tpms_wheel + 0.5) - 1
    src = int(p.blowout_compensation_detection)  # 0 wheel speeds, 1 TPMS, 2 both
    sources = 0
    cand = -1
    if src == 0:
        cand, sources = cand_ws, SRC_WS
    elif src == 1:
        cand, sources = cand_tp, SRC_TPMS
    elif cand_ws >= 0 and cand_ws == cand_tp:
        cand, sources = cand_ws, SRC_WS + SRC_TPMS
    elif cand_tp >= 0 and braking > 0.5:
        cand, sources = cand_tp, SRC_TPMS  # TPMS path: a braked blown wheel shows no over-speed
    if mode == REJECTED:
        if cand == rejected:
            cand = -1  # the rejected signature does not re-trigger
        if still or cand_tp == rejected:
            st[S_CLEAR_S] = 0.0
        else:
            st[S_CLEAR_S] += dt
            if st[S_CLEAR_S] >= p.blowout_compensation_detection_delay_s - 1e-9 and cand < 0:
                n_events = log_event(events, n_events, t, machine_id, mode, IDLE, G_CLEARED)
                mode = IDLE
                st[S_MODE] = mode
                st[S_REJECTED] = -1.0
    if mode == IDLE or mode == REJECTED:
        if cand >= 0 and cand == int(st[S_SUSPECT]):
            st[S_SUSPECT_S] += dt
            st[S_GB_RSUM] += yaw_rate  # (heading_return_mean_baseline_flag) the detection window's yaw error
            st[S_GB_RN] += 1.0
        else:
            st[S_SUSPECT] = cand
            st[S_SUSPECT_S] = 0.0
            st[S_GB_RSUM] = yaw_rate if cand >= 0 else 0.0
            st[S_GB_RN] = 1.0 if cand >= 0 else 0.0
        if cand >= 0 and st[S_SUSPECT_S] >= p.blowout_compensation_detection_delay_s - 1e-9:
            b = cand
            st[S_BLOWN] = b
            st[S_EXCLUDED] = b
            st[S_T_DET] = t
            st[S_SOURCES] = sources
            st[S_REJECTED] = -1.0
            # intact wheels' mean slip from the intact reference (only while the driver brakes)
            slip_mean = 0.0
            if braking > 0.5 and v_ref > 1.0:
                for i in range(4):
                    if i != b:
                        slip_mean += max((v_ref - vw[i]) / v_ref, 0.0) / 3.0
            target = OPPOSITE[b]
            new = BUILD
            reason = G_DETECTED
            st[S_LIMIT_CODE] = LIMIT_NONE
            if inlet_ok[target] < 0.5:
                target = _substitute(b)
                new = LIMITED
                reason = G_STUCK
                st[S_LIMIT_CODE] = LIMIT_OTHER_AXLE if inlet_ok[target] > 0.5 else LIMIT_NO_AUTHORITY
            _plan(st, b, target, new == LIMITED, slip_mean, a_x, a_y_ref, p_est, p)
            st[S_BETA_EST] = 0.0  # kinematic sideslip estimate, integrated from the detection
            st[S_BETA_DOT] = 0.0
            st[S_PSI_ERR] = 0.0
            st[S_GB_R0] = toward_blown_side(b, yaw_rate)  # (reject_heading_return_flag) the yaw error before any action
            if p.blowout_compensation_heading_return_mean_baseline_flag > 0.5 and st[S_GB_RN] > 0.5:
                # its mean over the detection window (the samples the detection itself used, detection_delay_s of the
                # same candidate; no action yet): one gyro-noise / transient sample is not a set-point for the stop
                st[S_GB_R0] = toward_blown_side(b, st[S_GB_RSUM] / st[S_GB_RN])
            st[S_GB_T0] = t
            st[S_REFUSED_DET] = 0.0
            st[S_GB_U0] = v_ref  # (reject_heading_return_flag 2) the speed its reference's understeer term is kept at
            st[S_GB_ON] = 0.0
            st[S_SPIN_EXITED] = 0.0
            st[S_OS_YAW_SEEN] = 0.0
            st[S_KEEP_S] = 0.0
            st[S_KEEP_PEAK] = 0.0
            st[S_BETA_OWN] = 0.0  # the model of the function's own yaw moment starts at the detection (yaw_net_flag)
            st[S_R_OWN] = 0.0
            st[S_OVERSPEED_S] = 0.0
            st[S_REAPPLY] = -1.0
            st[S_PAIR_LOW] = 0.0
            # TPMS path (single source, braking): confirmation by the released wheel pending (tpms_confirm_flag)
            st[S_HEALTHY_S] = 0.0 if (sources == SRC_TPMS and braking > 0.5
                                      and p.blowout_compensation_tpms_confirm_flag > 0.5) else -1.0
            code = unstable_code(yaw_rate_meas, 0.0, v_ref, p)
            b_dot = a_y_meas / v_ref - yaw_rate_meas if v_ref > 1.0 else 0.0
            spin = code != LIMIT_NONE or phase_plane_unstable(0.0, b_dot, p)  # phase_plane_flag: the spin-front trigger
            if spin and new == BUILD and spin_front_applies(b, target, yaw_rate_meas, code, 0.0, b_dot, inlet_ok, p):
                # already beyond the stable region rotating toward the blown side (rear blowout): the front wheel of the
                # compensating side instead (spin_front_flag), as from BUILD/HOLD below
                sub = _substitute(b)
                _plan(st, b, sub, True, slip_mean, a_x, a_y_ref, p_est, p)
                _plan_spin_front(st, sub, p_est, p)
                st[S_LIMIT_CODE] = LIMIT_SPIN_FRONT
                new = LIMITED
                reason = G_UNSTABLE
            elif code != LIMIT_NONE:
                # already beyond the stable region: the feed-forward cannot help (refusal, reason in the limit code)
                new = REFUSED
                reason = G_UNSTABLE
                st[S_LIMIT_CODE] = code
                st[S_TARGET] = -1.0
                st[S_REFUSED_DET] = 1.0  # (refused_blown_driver_flag) refused before any action
                _release_unconfirmed_latch(st)
            n_events = log_event(events, n_events, t, machine_id, mode, new, reason)
            mode = new
            st[S_MODE] = mode
    elif mode == BUILD or mode == HOLD or mode == LIMITED:
        st[S_ELAPSED] += dt
        b = int(st[S_BLOWN])
        tg = int(st[S_TARGET])
        toward = toward_blown_side(b, yaw_rate)  # yaw toward the blown side +
        single = st[S_SOURCES] < SRC_WS + SRC_TPMS - 0.5
        judged = toward
        if p.blowout_compensation_yaw_net_flag > 0.5:
            # yaw plausibility net of the function's own moment (issue #10 review finding A): releasing the blown wheel
            # from a braking driver's pressure yaws the car away from the blown side by itself; its expected yaw rate
            # (the ECU's single-track model of that moment) is added back before the yaw is judged - but only once the
            # released wheel shows the blowout's wheel-speed signature (a flat wheel, free of the brake, turns ~50 %
            # fast; a released healthy wheel rolls at the car's speed), for detection_delay_s as the detection: with a
            # false TPMS alarm the release alone must stay judged (netted out unconditionally, a false LF alarm under a
            # 150 N pedal at 60 km/h was never rejected: 1.87 m vs 0.19 m). The compensation pressure stays in the
            # judged yaw: with a real blowout it balances the blowout's moment, with a false detection it is the
            # unbalanced moment the rule must see. Only ever more lenient than the raw rule.
            m_rel = released_moment_nm(b, tg, braking, p_est, st[S_P_REQ] - st[S_P_START], p)
            linear = _opposite_linear(st, b, v_ref, a_x, p)
            bound = p.blowout_compensation_release_bound_flag > 0.5
            if bound and not linear:
                # beyond the linear region (release_bound_flag): the saturated opposite wheel carries its friction,
                # mu*F_z, and mu is at least the car's mean utilisation |a_x|/g (sum F_x = m*|a_x| <= mu*m*g): the
                # release's moment is bounded below by half-track * |a_x|/g * F_z,opposite (ECU nominal load)
                m_rel = min(m_rel, released_moment_bound_nm(b, a_x, p))
            r_own = toward_blown_side(b, own_yaw_step(st, toward_blown_side(b, -m_rel), v_ref, dt, p))
            if _candidate_ws(vw, v_ref, p.blowout_compensation_wheel_speed_threshold_frac, -1) == b:
                st[S_OVERSPEED_S] += dt
            else:
                st[S_OVERSPEED_S] = 0.0
            # beyond the linear region only where a yaw deficit is not the saturated front's understeer: with the
            # steered reference yaw toward the blown side (a curve toward it) the understeer of a saturated front reads
            # as yaw away from the blown side, and the raw yaw decides as before
            if st[S_OVERSPEED_S] >= p.blowout_compensation_detection_delay_s - 1e-9 and (
                    linear or (bound and toward_blown_side(b, r_ref) <= 0.0)):
                judged = toward + max(-r_own, 0.0)
        unconfirmed = False
        if st[S_HEALTHY_S] > -0.5:
            unconfirmed = released_wheel_healthy(st, b, v_ref, a_x, p_est, dt, p)
        b_dot = a_y_meas / v_ref - yaw_rate_meas if v_ref > 1.0 else 0.0  # beta_dot = a_y/u - r (kinematic)
        st[S_BETA_EST] += b_dot * dt
        st[S_BETA_DOT] = b_dot
        st[S_PSI_ERR] += toward_blown_side(b, yaw_rate) * dt  # yaw angle toward the blown side vs the steered reference
        code = unstable_code(yaw_rate_meas, st[S_BETA_EST], v_ref, p)
        # spin-front trigger (phase_plane_flag): the mu-0.8 bounds or the friction-free sideslip phase plane
        spin = code != LIMIT_NONE or phase_plane_unstable(st[S_BETA_EST], b_dot, p)
        keep = code != LIMIT_NONE and front_spin_keep(b, tg, yaw_rate, p, yaw_rate_meas, code, st[S_BETA_EST])
        if keep and p.blowout_compensation_front_spin_keep_arrest_flag > 0.5:
            # (front_spin_keep_arrest_flag) after the build, one time constant of the yaw mode (a quarter of its 2 %
            # settling time) for the counter-moment to act; a rotation toward the blown side still reaching new highs
            # after it is not being arrested: refused as before
            r_tw = toward_blown_side(b, yaw_rate_meas)
            if mode != BUILD:
                st[S_KEEP_S] += dt
            if st[S_KEEP_S] > 0.25 * settling_time_s(v_ref, p) and r_tw > st[S_KEEP_PEAK]:
                keep = False
            st[S_KEEP_PEAK] = max(st[S_KEEP_PEAK], r_tw)
        elif not keep:
            st[S_KEEP_S] = 0.0
            st[S_KEEP_PEAK] = 0.0
        spin_over = False
        if mode == LIMITED and st[S_LIMIT_CODE] == LIMIT_SPIN_FRONT:
            spin_over = spin_stopped(st, b, yaw_rate, code, b_dot, v_ref, inlet_ok, dt, p)
        # (blown_side_single_flag, session n N2) a single-source detection of a blown rear whose side's front is stuck
        # unbraked while the driver brakes: stand down as REJECTED does (blown_side_unbraked)
        side_unbraked = single and blown_side_unbraked(b, braking, inlet_ok, st, p)
        if (mode == BUILD or mode == HOLD) and inlet_ok[tg] < 0.5:
            # diagnosis after the detection: re-plan on the substitute wheel (slip as at detection)
            sub = _substitute(b)
            st[S_LIMIT_CODE] = LIMIT_OTHER_AXLE if inlet_ok[sub] > 0.5 else LIMIT_NO_AUTHORITY
            _plan(st, b, sub, True, st[S_SLIP_EST], a_x, a_y_ref, p_est, p)
            n_events = log_event(events, n_events, t, machine_id, mode, LIMITED, G_STUCK)
            mode = LIMITED
        elif single and ((judged < -p.blowout_compensation_abort_yaw_rate_radps and st[S_OS_YAW_SEEN] < 0.5)
                         or unconfirmed or side_unbraked):
            # (rear_oversteer_yaw_flag: S_OS_YAW_SEEN, the yaw once beyond the reference toward the blown side after
            # the build, confirms the flat - the yaw away afterwards is the held rear pair's, not a false alarm)
            n_events = log_event(events, n_events, t, machine_id, mode, REJECTED,
                                 G_YAW_IMPLAUSIBLE if judged < -p.blowout_compensation_abort_yaw_rate_radps
                                 else G_UNCONFIRMED if unconfirmed else G_BLOWN_SIDE_UNBRAKED)
            st[S_HEALTHY_S] = -1.0
            # the released wheel back to the driver at once (reject_reapply_flag; functions/esp.py): ABS's pulsed re-build
            # from the released level (55 -> 10 bar at a 500 N pedal) took 0.3 s on a front wheel, and the rear select-
            # low held a released rear at 3-9 bar for > 1 s, each with the other wheel of the axle at the lock level
            # - only a wheel that does not show the blowout's over-speed (a healthy one): a real flat wheel rejected by the
            # yaw (FL, braking envelope seed 5 #31) re-braked at once took the car to 0.334 m vs 0.333 m without the
            # function (0.224 m with ABS's pulsed re-build)
            healthy = wheel_speed_mean(st, b) <= v_ref * (1.0 + p.blowout_compensation_wheel_speed_threshold_frac)
            st[S_REAPPLY] = b if (braking > 0.5 and healthy and p.blowout_compensation_reject_reapply_flag > 0.5) else -1.0
            st[S_REAPPLY_P] = -1.0
            st[S_PAIR_LOW] = 1.0 if (st[S_REAPPLY] >= 2.0 and p.blowout_compensation_reject_pair_low_flag > 0.5) else 0.0
            # (reject_heading_return_flag) the heading the function's own release + build turned the car by, net of the
            # yaw error it had at the detection: the integral of (yaw error - baseline) from the detection to now
            t_psi = st[S_GB_T0] if p.blowout_compensation_heading_return_spin_exit_flag > 0.5 else st[S_T_DET]
            psi_own = st[S_PSI_ERR] - st[S_GB_R0] * (t - t_psi)
            # (heading_return_tpms_only_flag) only a TPMS-only detection: the rule's premise is a false TPMS alarm on
            # a wheel without the blowout's signature; a wheel-speed-only detection is the signature itself
            tpms_only = (st[S_SOURCES] > SRC_TPMS - 0.5 and st[S_SOURCES] < SRC_TPMS + 0.5) or \
                p.blowout_compensation_heading_return_tpms_only_flag < 0.5
            if (p.blowout_compensation_reject_heading_return_flag > 0.5 and braking > 0.5 and healthy
                    and tpms_only and psi_own < 0.0 and heading_return_kick_seen(st, toward, p)):
                st[S_GB_ON] = 1.0
                st[S_GB_PSI] = psi_own
                st[S_GB_B] = b
            mode = REJECTED
            st[S_REJECTED] = b
            st[S_BLOWN] = -1.0  # latch cleared: no wheel is held released any more, ABS/HBA run as without the function
            st[S_EXCLUDED] = -1.0
            st[S_TARGET] = -1.0
            st[S_CLEAR_S] = 0.0
            st[S_SUSPECT] = -1.0
            st[S_SUSPECT_S] = 0.0
        elif spin and mode != LIMITED and spin_front_applies(b, tg, yaw_rate_meas, code, st[S_BETA_EST], b_dot,
                                                             inlet_ok, p):
            # rear blowout, beyond the stable region, rotating toward the blown side: stop loading the rear axle and
            # brake the front wheel of the same side instead (spin_front_flag; module doc)
            sub = _substitute(b)
            _plan(st, b, sub, True, st[S_SLIP_EST], a_x, a_y_ref, p_est, p)
            _plan_spin_front(st, sub, p_est, p)
            st[S_LIMIT_CODE] = LIMIT_SPIN_FRONT
            n_events = log_event(events, n_events, t, machine_id, mode, LIMITED, G_UNSTABLE)
            mode = LIMITED
        elif spin_over:
            # the spin stopped, the car back inside the stable region (spin_exit_flag): the front wheel is released
            # (Q_NONE: the driver's and ABS's) and the rear compensating wheel re-planned to the balance of the blown
            # wheel's moment (eqs. 13-28, with the rear slip limit and the tire-capacity rule); a new spin moves the
            # counter-brake to the front again (BUILD/HOLD -> LIMITED above)
            _plan(st, b, OPPOSITE[b], False, st[S_SLIP_EST], a_x, a_y_ref, p_est, p)
            st[S_LIMIT_CODE] = LIMIT_NONE
            st[S_SPIN_EXITED] = 1.0
            st[S_RAMP_P0] = p_est[_substitute(b)]
            st[S_RAMP_T] = 0.0
            st[S_RAMP_DUR] = settling_time_s(v_ref, p)
            st[S_PSI_ERR] = 0.0  # the heading toward the blown side counted again from the exit (for a new spin's exit)
            st[S_GB_T0] = t  # (heading_return_spin_exit_flag) ... and the baseline taken off from the exit on
            n_events = log_event(events, n_events, t, machine_id, mode, BUILD, G_SPIN_STOPPED)
            mode = BUILD
        elif (code != LIMIT_NONE and not (mode == LIMITED and st[S_LIMIT_CODE] == LIMIT_SPIN_FRONT)
              and not keep):
            # the car has left the stable region: the feed-forward stands down (the target wheel back to the driver's
            # pressure and ABS, Q_NONE); a blown wheel confirmed by both sources stays released as in ENDED (it is flat),
            # a single-source detection is released from the latch (not confirmed)
            n_events = log_event(events, n_events, t, machine_id, mode, REFUSED, G_UNSTABLE)
            mode = REFUSED
            st[S_LIMIT_CODE] = code
            st[S_TARGET] = -1.0
            _release_unconfirmed_latch(st)
        elif mode == BUILD:
            if st[S_ELAPSED] >= st[S_T_VALVE] - 1e-9:
                n_events = log_event(events, n_events, t, machine_id, mode, HOLD, G_VALVE_DONE)
                mode = HOLD
        elif v_ref < p.blowout_compensation_min_speed_mps:
            n_events = log_event(events, n_events, t, machine_id, mode, ENDED, G_SLOW)
            mode = ENDED
            st[S_TARGET] = -1.0
        st[S_MODE] = mode
    st[S_MODE_ELAPSED] = st[S_ELAPSED]
    # requests
    b = int(st[S_BLOWN])
    tg = int(st[S_TARGET])
    if b >= 0:
        requests[b] = Q_RELEASE
        if mode == REFUSED and st[S_REFUSED_DET] > 0.5 and p.blowout_compensation_refused_blown_driver_flag > 0.5:
            # (refused_blown_driver_flag, 0 = the code before = released as in ENDED) refused AT the detection: the
            # function stands down before it acts, so the car is the one without the function (the driver's pressure
            # and ABS on every wheel, the ESP alone - the never-worse reference). The release of the blown wheel is the
            # first step of the paper's balance (eqs. 26-28, F_b = 0, the other front taking the counter-force); with
            # no balance planned it is a lone yaw moment away from the blown side and a lost share of the braking, in
            # a car already beyond the stable region: it slowed the spin without stopping it and the car slid on
            # faster and further (K1 r41 #264 without the fault: FL, 107 km/h, braking, refused at the detection,
            # 20.93 m vs none 10.86 m; given to the driver and ABS 10.09 m; G5 saw the same for a compensation kept
            # running past a detection-time refusal). A refusal during the compensation (the wheel already released
            # to ~0 bar) keeps it released as before: Q_NONE there would re-apply the driver's pressure at once.
            requests[b] = Q_NONE
        if p.blowout_compensation_blown_front_hold_flag > 0.5:
            blown_front_hold(st, b, tg, mode, braking, yaw_rate, r_ref, requests, p)
    # (ramp_refused_flag) the ramp only while the rear compensates (BUILD/HOLD): REFUSED after the exit is a car beyond
    # the bounds rotating AWAY from the blown side (toward it the spin-front rule takes over), and the spin-front wheel's
    # pressure is a moment in that rotation's direction - the feed-forward stands down there (Q_NONE), as at once
    ramp_modes = mode == BUILD or mode == HOLD or (p.blowout_compensation_ramp_refused_flag < 0.5 and mode != LIMITED)
    if (p.blowout_compensation_spin_release_ramp_flag > 0.5 and b >= 2 and st[S_SPIN_EXITED] > 0.5
            and ramp_modes and st[S_RAMP_T] < st[S_RAMP_DUR]):
        # spin_release_ramp_flag: after the exit the spin-front wheel's pressure is withdrawn linearly to 0 over the
        # settling time of the single-track yaw mode (settling_time_s at the exit speed), not dumped at once: its
        # counter-moment goes no faster than the car's yaw mode settles, and the rear's re-planned balance builds
        # meanwhile (valve time, eq. 30); above the ramp the wheel is dumped, below it held (never built)
        st[S_RAMP_T] += dt
        sub = _substitute(b)
        allowed = st[S_RAMP_P0] * (1.0 - st[S_RAMP_T] / st[S_RAMP_DUR])
        if p.blowout_compensation_ramp_driver_floor_flag > 0.5:
            # (ramp_driver_floor_flag) the ramp withdraws the function's own pressure, never the driver's: not below the
            # master pressure (the front wheel's source; released at once, Q_NONE, it goes to the driver's pressure)
            allowed = max(allowed, p_mc)
        requests[sub] = Q_RELEASE if p_est[sub] > allowed + PRESSURE_MARGIN_PA else Q_HOLD
    if tg >= 0 and inlet_ok[tg] > 0.5:
        if mode == BUILD:
            requests[tg] = Q_BUILD
        elif mode == LIMITED:
            requests[tg] = Q_BUILD if st[S_ELAPSED] < st[S_T_VALVE] else Q_HOLD
            if st[S_LIMIT_CODE] == LIMIT_SPIN_FRONT and toward_blown_side(b, yaw_rate_meas) < -p.esp_yaw_dump_rate_radps:
                # the spin arrested and the car rotating back away from the blown side faster than the ESP's yaw dump
                # rate (the limit it puts on any brake-induced yaw moment): dumped; re-built by the ESP below it
                requests[tg] = Q_RELEASE
        elif mode == HOLD:
            requests[tg] = Q_HOLD
            toward = toward_blown_side(b, yaw_rate)
            if p.blowout_compensation_closed_loop_flag > 0.5:
                if toward > p.blowout_compensation_yaw_deadband_radps:
                    requests[tg] = Q_PULSE
                elif toward < -p.blowout_compensation_yaw_deadband_radps:
                    requests[tg] = Q_RELEASE
            elif toward < -p.esp_yaw_dump_rate_radps:
                # over-compensation limiter (feed-forward mode): while the car yaws away from the blown side
                # faster than the ESP's yaw dump rate (the limit it puts on any brake-induced yaw moment, 5 deg/s)
                # the compensating wheel is dumped; once the yaw is back under the rate the request is HOLD again and
                # the ESP's re-build rule (functions/esp.py, meant for after an ABS dump) re-builds it to S_P_REQ - it
                # is not held where it is (independent review); a trusted detection is not released (falsification
                # findings). 2 deg/s (the plausibility threshold) cut
                # the needed correction after a late detection (100 km/h front, 0.2 s delay: 1.07 -> 2.35 m)
                requests[tg] = Q_RELEASE
        if tg >= 2 and p.blowout_compensation_slip_limit_flag > 0.5 and mode != ENDED:
            # rear compensating wheel kept in the tire's linear region (linear_slip_limit_frac, ECU nominal data):
            # above it the added pressure is dumped down to the driver's pressure (never below: a braking driver's
            # wheel is the driver's and ABS's) and the target lowered to what the wheel carries (HOLD then holds it,
            # no re-build) - a rear wheel braked into saturation loses the lateral force the axle with the flat tire
            # needs, the rear swings out and the car spins toward the blown side (falsification seed 3: 12-18 % slip,
            # below ABS's 20 % threshold, 16.6 m vs 5.1 m without compensation)
            _, cap = rear_linear_limit(tg, st[S_FZ_TARGET], a_y_ref, p)
            st[S_SLIP_CAP] = cap
            # the floor: the driver's CURRENT pressure at this wheel (the measured master pressure through the
            # proportioning valve, as the ESP passes it on; ABS guards it), not the pressure at detection S_P_START
            # (0 when the pedal comes after the detection: the limit then dumped every later driver's pressure on the
            # wheel and, with the flat wheel released, left the rear axle unbraked - F2 CMA 2026 #46, RR 83.5 km/h:
            # 3.26 m vs 2.97 m without compensation)
            p_floor = st[S_P_START]
            if braking > 0.5:
                p_floor = max(p_floor, proportioned_pa(max(p_mc, 0.0), p.master_cylinder_proportioning_knee_pa,
                                                       p.master_cylinder_proportioning_slope_frac))
            if p.blowout_compensation_signal_filter_flag > 0.5:
                # filtered slip (moving mean, v_ref from the same window), persistence, hysteresis (signal_filter_flag;
                # raw samples with 0.1 rad/s wheel-speed noise dumped and latched the target on one sample: RR 60 km/h
                # 0.72 -> 2.5 m, 7.5 m = no compensation at 0.2 rad/s)
                v_s = slip_reference_mps(st, b, tg, v_ref, braking)
                s_tg = (v_s - wheel_speed_mean(st, tg)) / max(v_s, 1.0)
                # a raw sample far above the cap (beyond RAW_SIGMAS x the noise the free wheels show) is evidence at
                # once, without the filter's lag: the build's overshoot is caught as by the raw code (a light-braking
                # rear point, F's P5: 0.51 m raw, 1.51 m on the filtered slip alone, none 0.75 m)
                s_raw = (v_s - vw[tg]) / max(v_s, 1.0)
                # (the noise term is >= 0: only a sample above the cap needs it)
                raw_over = s_raw > cap and s_raw > cap + RAW_SIGMAS * wheel_noise_mps(st, b, tg, dt) / max(v_s, 1.0)
                if s_tg > cap:
                    st[S_SLIP_HIGH_S] += dt
                elif s_tg <= (1.0 - SLIP_HYST_FRAC) * cap:
                    st[S_SLIP_HIGH_S] = min(st[S_SLIP_HIGH_S], 0.0)
                if st[S_SLIP_HIGH_S] >= SLIP_PERSIST_S - 1e-9 and s_tg > cap:
                    # the target lowered to the pressure that gives the cap slip, scaled from the window's mean
                    # pressure and slip (same window centre; slip ~ brake force ~ pressure in the linear region):
                    # following the live estimate down while the lagging filtered slip is still above the cap
                    # over-dumped (RR 60 km/h, no noise: 0.72 -> 3.44 m); a further lowering needs a fresh window of
                    # evidence (the window length before the persistence counts again), not the same lagging one
                    st[S_SLIP_LIMITED] = 1.0
                    p_cap = _cap_slip_pressure(st, tg, v_s, cap, dt, p)
                    st[S_P_REQ] = max(min(st[S_P_REQ], p_cap), st[S_P_START])
                    st[S_SLIP_HIGH_S] = -WS_WINDOW_N * dt
                if st[S_SLIP_LIMITED] > 0.5:
                    if p_est[tg] > max(st[S_P_REQ], p_floor) + PRESSURE_MARGIN_PA:
                        requests[tg] = Q_RELEASE
                    elif mode == BUILD:
                        requests[tg] = Q_HOLD  # once limited, the build does not start again
                over = raw_over
            else:
                s_tg = (v_ref - vw[tg]) / max(v_ref, 1.0)
                over = s_tg > cap
            if over:
                st[S_SLIP_LIMITED] = 1.0
                st[S_P_REQ] = max(min(st[S_P_REQ], p_est[tg]), st[S_P_START])
                lim_dump = (p.blowout_compensation_slip_limit_yaw_flag > 0.5 and mode == HOLD
                            and requests[tg] == Q_RELEASE and p.blowout_compensation_closed_loop_flag < 0.5)
                if not lim_dump:
                    # (slip_limit_yaw_flag, session o O6; 0 = the code before: the floor's HOLD also overrode the
                    # over-compensation limiter's dump) the limiter above dumps the compensating wheel while the car
                    # yaws away from the blown side beyond the ESP's yaw dump rate - the ESP's limit on any
                    # brake-induced yaw moment comes before the driver's-pressure floor of the slip limit (O6: rrL
                    # #43, RL 90.8 km/h mu 0.36, RR held at 64 bar under the floor while the car yawed right at
                    # 0.2-0.48 rad/s with RL released, off the road 26.1 s early; twin on, 2.56 m)
                    requests[tg] = Q_RELEASE if p_est[tg] > p_floor + PRESSURE_MARGIN_PA else Q_HOLD
            elif mode == BUILD and st[S_SLIP_LIMITED] > 0.5:
                requests[tg] = Q_HOLD  # once limited, the build does not start again: hold at the lowered target
        if p.blowout_compensation_tire_capacity_flag > 0.5 and st[S_LIMIT_CODE] != LIMIT_SPIN_FRONT:
            # (not on the spin-front wheel: its lost lateral force is the intended understeer)
            tire_capacity_rule(st, tg, vw, v_ref, a_y_ref, braking, p_est, requests, p, dt, a_x)
        if p.blowout_compensation_understeer_flag > 0.5:
            understeer_rule(st, b, tg, mode, braking, r_ref, yaw_rate_meas, p_est, requests, p, dt, v_ref)
    if p.blowout_compensation_braking_rule_flag > 0.5:
        braking_rule(st, b, tg, mode, braking, a_x, a_y_ref, yaw_rate, p_mc, p_est, p, r_ref, a_y_meas, v_ref)
    if (p.blowout_compensation_own_stuck_front_flag > 0.5 and 0 <= b < 2 and tg == OPPOSITE[b]
            and inlet_ok[b] < 0.5 and braking > 0.5 and (mode == BUILD or mode == HOLD)):
        # (own_stuck_understeer_flag) the steered curve judged at the detection speed (S_GB_U0): the path curvature the
        # driver asked as a yaw rate at that speed, which the stop's falling speed does not take inside the dead band
        r_curve = reference_yaw_rate(steer_rad, st[S_GB_U0], p) if st[S_GB_U0] > 1.0 else r_ref
        own_stuck_front(st, b, tg, yaw_rate, p_est, p_mc, requests, p, r_curve, v_ref)
    if (p.blowout_compensation_substitute_yaw_limit_flag > 0.5 and mode == LIMITED
            and st[S_LIMIT_CODE] == LIMIT_OTHER_AXLE and b >= 2 and 0 <= tg < 2):
        substitute_yaw_limit(b, tg, yaw_rate, p_est, requests, p, st)
    if p.blowout_compensation_blown_side_fault_flag > 0.5 and b >= 0:
        blown_side_fault(st, b, tg, mode, braking, inlet_ok, p_est, p_mc, requests, p, yaw_rate)
    if p.blowout_compensation_diagonal_fault_flag > 0.5 and b >= 2:
        diagonal_fault(st, b, tg, mode, braking, inlet_ok, yaw_rate, p_est, requests, p, r_ref)
    if (p.blowout_compensation_front_substitute_rear_flag > 0.5 and mode == LIMITED
            and st[S_LIMIT_CODE] == LIMIT_OTHER_AXLE and 0 <= b < 2 and tg >= 2):
        front_substitute_rear(b, tg, braking, yaw_rate, r_ref, p_est, requests, p, st)
    elif p.blowout_compensation_front_substitute_rear_flag > 1.5:
        st[S_M7_SET] = 0.0  # (value 2, M7) outside the substitute rear's LIMITED episode: nothing latched
    if st[S_GB_ON] > 0.5:
        y_gb = yaw_rate
        if p.blowout_compensation_reject_heading_return_flag > 1.5:
            y_gb = yaw_rate_meas - heading_return_reference(steer_rad, v_ref, st[S_GB_U0], p)
        reject_heading_return(st, mode, braking, y_gb, v_ref, p_est, requests, p, dt)
    return n_events


@nb.njit(cache=True, nogil=True, error_model="numpy")
def substitute_yaw_limit(b, tg, yaw_err, p_est, requests, p, st):
    """``substitute_yaw_limit_flag`` (0 = the code before; tire_blowout_findings.md K2, session k). LIMITED on the
    substitute front (a REAR blowout b whose opposite rear's inlet is stuck closed, limit code 1: ``_substitute`` brakes
    the front on the other side): the front on the BLOWN side is the front whose brake force yaws the car toward the
    blown side - the direction the flat tire already pulls. Without the function the ESP's yaw-moment limitation (GMA,
    functions/esp.py: a front wheel is held while the yaw rate toward its side exceeds esp.yaw_hold_rate and dumped
    above esp.yaw_dump_rate; Bosch Automotive Handbook, ABS/ESP yaw-moment limitation) governs that wheel as soon as
    the other front's ABS cycles alone; with the function the compensation's block masks the substitute's ABS activity
    and ends a GMA already running on the blown side's front (esp.py: 'a GMA the compensation's wheel started is not
    a split-mu GMA'), so the blown side's front went to the driver's / pump pressure and its brake moment cancelled the
    substitute's (bb47 #99: FL 1 -> 46 bar at the detection against the twin's 1 bar). The same yaw limitation with the
    same two thresholds, on the yaw error the compensation judges (net of the steered reference, ``yaw_err``; the raw
    yaw rate, as the GMA, counted a curve toward the blown side and made 23 points worse by > 0.05 m against 8):
    beyond esp.yaw_dump_rate the blown side's front is released; beyond esp.yaw_hold_rate it is released while it is
    more than 1 bar above the substitute (the GMA limits the fronts' pressure DIFFERENCE; a 'hold' request is not
    available here - Q_HOLD re-builds a wheel to the compensation's target S_P_REQ, functions/esp.py). The substitute
    itself is left to the compensation and ABS. 444 stuck rear points: 62 never-worse violations -> 23 (findings K2).

    Value 2 (session k K7, RK1's latched hold): the GMA HOLDS a front between the two yaw rates - its pressure does not
    rise there. Value 1 released it only while it was more than 1 bar above the substitute, so between those dumps the
    front's own ABS/HBA pulsed re-build raised it again (P22: FL 21-30 bar sawtooth against the twin's ~1 bar). With 2
    the front's line level is latched when the yaw error enters the band (or at the last dump period above the dump
    rate) and the front is released while it is more than 1 bar (the same margin as value 1) above that level; below
    esp.yaw_hold_rate the latch is dropped (S_SUB_HOLD, -1)."""
    w = b - 2  # the front on the blown side
    toward = toward_blown_side(b, yaw_err)
    if toward > p.esp_yaw_dump_rate_radps:
        requests[w] = Q_RELEASE
        if p.blowout_compensation_substitute_yaw_limit_flag > 1.5:
            st[S_SUB_HOLD] = st[S_P_LINE + w]
    elif toward > p.esp_yaw_hold_rate_radps:
        latched = False
        if p.blowout_compensation_substitute_yaw_limit_flag > 1.5:
            if st[S_SUB_HOLD] < 0.0:
                st[S_SUB_HOLD] = st[S_P_LINE + w]
            latched = st[S_P_LINE + w] > st[S_SUB_HOLD] + PRESSURE_MARGIN_PA
        if latched or p_est[w] > p_est[tg] + PRESSURE_MARGIN_PA:
            requests[w] = Q_RELEASE
    elif p.blowout_compensation_substitute_yaw_limit_flag > 1.5:
        st[S_SUB_HOLD] = -1.0


@nb.njit(cache=True, nogil=True, error_model="numpy")
def blown_side_unbraked(b, braking, inlet_ok, st, p):
    """``blown_side_single_flag`` (0 = the code before; session n N2, tire_blowout_findings.md N2): blown_side_fault's
    premises - a blown REAR b whose side's FRONT (RL <-> FL, RR <-> FR) has its inlet diagnosed stuck closed with no
    brake in it (the pressure the fault trapped, S_L6_TRAPPED, below esp.plausibility_pressure: L6's value 3) while the
    driver brakes (brake-light switch) - for a detection the caller has found SINGLE-source (wheel speeds or TPMS
    alone). Paper 004's balance (eqs. 9, 22-28) with the stuck front's force gone: the release (P7, F_b = 0) leaves the
    blown side with no brake, the pedal's front brake acts on the other side alone, b_f*F_front away from the blown
    side, and the counter-brake (eq. 28, the other rear) adds to it - no counter-brake >= 0 balances that (L1). For a
    two-source detection blown_side_fault (value 4) stands the brakes down and keeps the detection. For a single-source
    one RL4 kept the paper's release (the confirmation probe), and M5 showed that what ended it on these points was the
    yaw_implausible rejection (f_r3 #22: 0.57 s after the detection); standing the brakes down while keeping the
    detection (L6's value 3) left the ESP in the function's modes (TPMS-named reference, rear select-low exceptions,
    GMA suppressed; M5's #492). So the caller stands the function down exactly as a rejection does (REJECTED: the
    released wheel re-applied at once, the rear pair select-low, the latch cleared; guard blown_side_unbraked): the
    no-compensation car on every brake. No new number. Not for a blown front (blown_side_front_flag governs there)."""
    if p.blowout_compensation_blown_side_single_flag < 0.5 or b < 2 or braking < 0.5:
        return False
    s = b - 2
    return inlet_ok[s] < 0.5 and 0.0 <= st[S_L6_TRAPPED + s] < p.esp_plausibility_pressure_pa


@nb.njit(cache=True, nogil=True, error_model="numpy")
def blown_side_fault(st, b, tg, mode, braking, inlet_ok, p_est, p_mc, requests, p, yaw_err):
    """``blown_side_fault_flag`` (0 = the code before; session l L1, tire_blowout_findings.md L1, K1's r41 #360). The
    wheel on the blown wheel's SIDE on the other axle (FL <-> RL, FR <-> RR) has its inlet diagnosed stuck closed: after
    the paper's release of the blown wheel (P7, eqs. 26-28: F_b = 0) that side has no brake at all, so a braking
    driver's whole braking force is on the other side - a yaw moment away from the blown side set by the pedal, not by
    the blowout, and in the same direction as the counter-brake. The balance of eqs. 26-28 (a counter-brake >= 0 on the
    other side against the blown wheel's drag) cannot balance it; the only brake the blown side has left is the blown
    wheel itself. So while the driver brakes (brake-light switch) the blown wheel is not released (Q_NONE: the driver's
    pressure and ABS, as in the car without the function, where the rear select-low / ABS keep it braked) and the
    counter-brake wheel keeps no added pressure (the braking rules' targets cleared; Q_NONE = the driver's pressure and
    ABS, dumped (Q_RELEASE) while it is more than 1 bar above what the car without the function gives it: a rear the
    blown rear's pressure - the ABS rear select-low keeps the pair equal there -, a front the driver's master pressure
    - a counter-brake built before the pedal stayed held above the pair, RL 37-42 vs RR 30-33 bar at r41 #360): the
    function stands down to the no-compensation car on the brakes and reports why (limit code LIMIT_BLOWN_SIDE, unless
    a refusal / other limit code already says more). Without the pedal the blown side has no driver's pressure to lose
    and the paper's compensation runs as before. No threshold (a diagnosis rule).
    A blown REAR only (the blown side's FRONT stuck): there the side loses its front brake, the largest one (the rears
    run on the proportioned pressure), and the release left it with none. With a blown FRONT and its side's rear stuck
    the side loses only a proportioned rear brake and the front braking rule's four-force balance (``braking_rule``,
    rear pair cap) governs: applied there too the rule made 14 of 18 such changed points of the lead's fault sets worse
    (4 new never-worse violations, f_r41 #480 +0.080 -> -0.916, f_r3 #1 +0.329 -> -0.616; tire_blowout_findings.md L1).

    Value 2 (session l L6, tire_blowout_findings.md L6): the counter-brake rear is compared with the blown rear on the
    ECU's line-lag estimate (A_P_LINE, in S_P_LINE from functions/esp.py) instead of A_P_EST. At the pedal the released
    blown rear goes to Q_NONE = W_N, and A_P_EST in W_N takes the source (the driver's proportioned pressure) at once
    (esp._estimate): at r41 #360 it read 52 bar with 9.5 in the wheel, so value 1 stopped dumping RL at 14.7 bar and
    the pair's common ABS modulation (select-low: both rears the same mode) carried the offset for seconds (RL - RR 4-5,
    later 1-2 bar; twin 0) - a moment away from the blown side the lane follower over-corrected (0.193 vs the twin's
    0.172 m). On the line estimate the dump runs until the pair carries one pressure: 0.169 m. A front compensating
    wheel keeps the master pressure as its ceiling.
    Value 3: value 2 and the premise checked - the blown side's front is unbraked: the pressure the fault trapped in
    it (S_L6_TRAPPED, the ECU's line estimate when its inlet was first diagnosed stuck) below esp.plausibility_pressure
    (the ESP's own 'unbraked' threshold). A front stuck while the driver brakes keeps the brake it had (L3's
    fault_time: t_r7 #219, FR stuck at 1.36 s holding 52.8 bar): the blown side is braked, the paper's release stands
    (value 2 there: 2.213 m vs the twin's 2.084; value 3 1.223 m as value 0).
    Value 4 (session l RL4, tire_blowout_findings.md RL4): value 3 for a detection both sources agree on (S_SOURCES =
    wheel speeds + TPMS); a single-source detection keeps the paper's release. With the pedal before the detection the
    detection is TPMS-only: its release is the confirmation probe (``tpms_confirm_flag``: the freed flat spins up) and its
    yaw is judged net of that release (``yaw_net_flag``). With the blown side's front stuck the pedal itself yaws the car
    away from the blown side, so such a detection was rejected (yaw_implausible) 5 ms after it; value 3 had then only
    suppressed the 5 ms release and its re-apply and reported code 6 through the REJECTED mode: f_r41 #134 +0.010 ->
    -0.021, t_r41 #470 +0.003 -> -0.020 m (L6's two new violations; +-2 % speed around them: worse than 0 in 16/21 and
    21/21 points).

    ``blown_side_front_flag`` (session m M2, tire_blowout_findings.md M2; 0 = the code before: a blown rear only): a
    blown FRONT whose side's REAR inlet is diagnosed stuck, with every premise and gate above (the pedal, the stuck
    wheel unbraked at its diagnosis, value 4's two-source detection). The blown side is then unbraked while the driver
    brakes, but unlike the rear case the front balance still holds: the paper's release and the braking rule's counter-
    brake act on the same (front) axle. What the release does not contain is the free REAR's brake, b_r*F_rr alone,
    a moment away from the blown side (eqs. 22-28 assume the rears brake alike). Value 2: the rear pair select-low on
    pressure - the free rear held at no more than 1 bar above the pressure the fault trapped in the stuck rear
    (S_REAR_CAP, as own_stuck_front's rear pair; the ESP's rear select-low, Bosch Automotive Handbook) while the yaw
    error (steered reference) points away from the blown side beyond the dead band (the braking rule's own gate); the
    front balance stays the paper's; limit code 6. Value 3 (session m M2b, shipped): value 2's gate with a hysteresis
    from the ESP's numbers - opened beyond esp.yaw_hold_rate away from the blown side, closed only beyond the dead band
    toward it (S_M2B_GATE); value 2's dead-band gate toggled at the edge (RM2's ft s31 #154). Value 1 (measured, NOT shipped): value 1..4's stand-down (the
    blown front to the driver and ABS, the counter-brake front to the master pressure): the function's counter-brake
    beats the twin on most such points and the stand-down gave it back - own set of 192 points 10 -> 15 violations,
    9 new, 76 worse (L1's v1 found the same)."""
    if b < 2 and p.blowout_compensation_blown_side_front_flag < 0.5:
        return  # a blown REAR only (its side's front stuck): measured, see the docstring
    # the blown side's wheel on the other axle (FL <-> RL, FR <-> RR); (blown_side_front_flag, session m M2) a blown
    # FRONT with its side's REAR stuck as well
    s = b - 2 if b >= 2 else b + 2
    # (review RL2) code 6 says "no counter-brake is added" (a blown rear; a blown front, review RM2: "the free rear held
    # select-low"): once the rule stands aside (the pedal released, the paper's
    # compensation back - measured at r41 #360 with the pedal released at 2.6 s: RL 32 bar, RR 1.4 bar, code still 6 to
    # the end) the code it wrote is taken back; it only ever replaced LIMIT_NONE. Since session o braking_rule reads 6
    # (blown_side_stop_flag, O4): it runs before this function, so it follows code 6 one ESP period late (5 ms, bounded)
    stand_aside = inlet_ok[s] > 0.5 or braking < 0.5
    # (blown_side_spin_front_flag, review RL2, candidate, 0 = the code before) nor while the spin-front rule governs
    # (code 5: the blown rear released and the compensating side's front braked against a rotation TOWARD the blown
    # side): the blown rear's brake is a moment
    # toward the blown side and takes the rear axle's lateral force - the spin's direction (f_r41 #378: RR 10-44 bar
    # for 101 samples of code 5 while the code said "rear wheel released")
    if p.blowout_compensation_blown_side_spin_front_flag > 0.5 and st[S_LIMIT_CODE] == LIMIT_SPIN_FRONT:
        stand_aside = True
    if stand_aside:
        if st[S_LIMIT_CODE] == LIMIT_BLOWN_SIDE:
            st[S_LIMIT_CODE] = LIMIT_NONE
        st[S_M2B_GATE] = 0.0  # (value 3) a new pedal application starts with the gate closed (final read, session m)
        return
    if p.blowout_compensation_blown_side_fault_flag > 2.5 and st[S_L6_TRAPPED + s] >= p.esp_plausibility_pressure_pa:
        return  # (value 3) the stuck front holds a brake: the side is not unbraked, the paper's release stands
    if p.blowout_compensation_blown_side_fault_flag > 3.5 and st[S_SOURCES] < SRC_WS + SRC_TPMS - 0.5:
        return  # (value 4, RL4) a single-source detection: the paper's release is its confirmation probe (see above)
    if b < 2 and p.blowout_compensation_blown_side_front_flag > 1.5:
        # (blown_side_front_flag 2, session m M2) a blown FRONT, its side's rear stuck: the paper's front balance stays
        # (blown front released, the braking rule's counter-brake) and the rear pair is held select-low on pressure -
        # the free rear at no more than 1 bar above what the stuck rear carries (the pressure its fault trapped), as
        # own_stuck_front's rear pair (S_REAR_CAP; functions/esp.py holds / dumps above it), while the yaw error
        # (steered reference) points AWAY from the blown side beyond the dead band (the braking rule's own gate): the
        # moment the lone rear brake makes
        # (value 3, session m M2b, tire_blowout_findings.md M2b) a hysteresis from the ESP's own numbers: the gate
        # opens once the yaw error points away from the blown side beyond esp.yaw_hold_rate (the ESP's threshold for
        # holding a wheel whose brake yaws the car; 2 deg/s) and stays open (S_M2B_GATE) until the error points TOWARD
        # the blown side beyond the dead band (there the lone rear's moment away helps). Value 2's gate at the dead
        # band's edge toggled at ft s31 #154 (error -0.017..+0.006 rad/s vs db 0.0175): the counter-brake FR then
        # settled on an 8.7 bar hold where value 0 ABS-cycles 4-21 bar (0.786 m vs 0.633, twin 0.698)
        tw = toward_blown_side(b, yaw_err)
        db = p.blowout_compensation_yaw_deadband_radps
        gate = tw < -db
        if p.blowout_compensation_blown_side_front_flag > 2.5:
            # the slot holds the blown wheel + 1 it was opened for: a later detection of another wheel (the sign of
            # toward_blown_side flips) does not inherit it (final read, session m)
            if tw < -p.esp_yaw_hold_rate_radps:
                st[S_M2B_GATE] = b + 1.0
            elif st[S_M2B_GATE] > 0.5 and tw > db:
                st[S_M2B_GATE] = 0.0
            gate = st[S_M2B_GATE] == b + 1.0
        if gate:
            cap = max(st[S_L6_TRAPPED + s], 0.0) + PRESSURE_MARGIN_PA
            if st[S_REAR_CAP] < 0.0 or st[S_REAR_CAP] > cap:
                st[S_REAR_CAP] = cap
        if st[S_LIMIT_CODE] == LIMIT_NONE:
            st[S_LIMIT_CODE] = LIMIT_BLOWN_SIDE
        return
    requests[b] = Q_NONE
    if tg >= 0 and (mode == BUILD or mode == HOLD or mode == LIMITED):
        ceiling = p_est[b] if tg >= 2 else p_mc
        p_tg = p_est[tg]
        if p.blowout_compensation_blown_side_fault_flag > 1.5:
            # (value 2, 3) both on the ECU's line-lag estimate: A_P_EST of the re-braked blown rear (W_N) is the source
            p_tg = st[S_P_LINE + tg]
            if tg >= 2:
                ceiling = st[S_P_LINE + b]
        requests[tg] = Q_RELEASE if p_tg > ceiling + PRESSURE_MARGIN_PA else Q_NONE
        st[S_P_BRAKE] = -1.0
        st[S_REAR_CAP] = -1.0
    if st[S_LIMIT_CODE] == LIMIT_NONE:
        st[S_LIMIT_CODE] = LIMIT_BLOWN_SIDE


@nb.njit(cache=True, nogil=True, error_model="numpy")
def diagonal_fault(st, b, tg, mode, braking, inlet_ok, yaw_err, p_est, requests, p, r_ref):
    """``diagonal_fault_flag`` (0 = the code before; session m M1, tire_blowout_findings.md M1): the DIAGONAL fault.
    A blown REAR b whose OTHER side's FRONT inlet is diagnosed stuck closed (RR blown + FL stuck, RL blown + FR stuck),
    compensated (BUILD/HOLD/LIMITED) while the driver brakes. The paper's balance (eqs. 9, 22-28: the yaw moment of the
    four brake forces plus the flat's drag) with the stuck front's force gone: M toward the blown side =
    b_f*F_front(blown side) + b_r*(D + F_b) - b_r*F_tg, the front term no longer cancelled by the other front. The
    paper's counter-brake (eq. 28: the intact rear of the blown axle, tg) is sized against the drag D alone and is held
    to the rear's linear limit, so it cannot carry the pedal's one-sided front brake as well: f_r41 #318 (RR blown, FL
    stuck, 97 km/h, pedal 0.49): FR 45-60 bar by the HBA pump, FL 0, RR released, RL 55-81 bar; yaw toward the blown
    side -0.177 against the twin's -0.104 rad/s at 1.25 s, refused at 1.62 s, 20.33 m against the twin's 17.31.
    ESP practice for a front pair braked on one side is the yaw-moment limitation (GMA, functions/esp.py; Bosch
    Automotive Handbook, ABS/ESP yaw-moment build-up delay): it limits the FRONTS' pressure difference while the yaw rate
    toward the braked side builds up. Here the other front is stuck, so the GMA's comparison is against it. The rule is
    K2's ``substitute_yaw_limit`` (the blown side's front released beyond esp.yaw_dump_rate, and beyond esp.yaw_hold_rate
    while more than 1 bar above the other front; yaw error net of the steered reference) with the stuck front as the
    reference wheel - the same thresholds, no new number. The counter-brake rear is left to the compensation.
    Premise as L6's value 3 (``blown_side_fault``): the stuck front is unbraked - the pressure the fault trapped in it
    (S_L6_TRAPPED, the ECU's line estimate when its inlet was first diagnosed stuck, recorded with this flag on too)
    below esp.plausibility_pressure; a front stuck while the driver brakes (L3's fault_time) keeps its brake and the
    front pair is not one-sided.
    Value 2: value 1 except with the sideslip phase-plane state outside the stable region
    (``phase_plane_unstable``, L2's gate in ``front_substitute_rear``): there the car already rotates on a saturated
    rear axle and is refused moments later; releasing the braked front only kept its speed up, and a spinning car's
    lateral excursion grows with its speed (faultsT t_r41 #346, RR blown, FL stuck at 0.07 s, mu 0.31, 116 km/h, pedal
    at 2.44 s: the car beyond the stable region at the pedal, FR held at 2.4 bar against the twin's 20-37 until the
    refusal at 2.73 s; 14.999 m against the twin's 14.768 - a new violation at value 1, +0.346 at 0 and 2).
    Value 3 (shipped, review RM1): value 2 except in a curve steered toward the blown side (``front_substitute_rear``'s
    curve gate): RM1's targeted t97 #64 (RL blown, FR stuck, 650 m left curve) +0.150 at 0, -0.545 at 2, +0.150 at 3."""
    if b < 2 or braking < 0.5:
        return
    w = b - 2  # the blown side's front
    o = OPPOSITE[w]  # the other side's front: the stuck one
    if inlet_ok[o] > 0.5 or inlet_ok[w] < 0.5:
        return
    if st[S_L6_TRAPPED + o] >= p.esp_plausibility_pressure_pa:
        return  # the stuck front holds the brake it had when it stuck (L6's premise): the front pair is not one-sided
    if p.blowout_compensation_diagonal_fault_flag > 1.5 and phase_plane_unstable(st[S_BETA_EST], st[S_BETA_DOT], p):
        return  # (value 2) L2's phase-plane gate: beyond the stable region the front's release only keeps the speed up
    if (p.blowout_compensation_diagonal_fault_flag > 2.5
            and curve_toward_blown_side(b, r_ref, p)):
        return  # (value 3, RM1) L2's curve gate: a curve steered toward the blown side (front_substitute_rear's gate)
    if mode == BUILD or mode == HOLD or mode == LIMITED:
        substitute_yaw_limit(b, o, yaw_err, p_est, requests, p, st)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def front_substitute_rear(b, tg, braking, yaw_err, r_ref, p_est, requests, p, st):
    """``front_substitute_rear_flag`` (0 = the code before; tire_blowout_findings.md L2, session l): K2's
    ``substitute_yaw_limit`` for a blown FRONT. LIMITED on the substitute REAR (a front blowout b whose opposite front's
    inlet is stuck closed, limit code 1: ``_substitute`` brakes the rear on the other side), while the driver brakes.
    Both fronts are then unbraked (the blown one released, the other stuck) and the car brakes on its rears alone. The
    rear on the BLOWN side is the wheel whose brake force yaws the car toward the blown side. Without the function
    the ESP's rear select-low keeps both rears at one pressure (functions/esp.py: both rears follow the more critical
    request), so the rear axle adds no yaw moment; with the function the substitute is the compensation's wheel (its
    requests bypass the select-low) and the blown side's rear took the driver's / HBA pump pressure ABOVE the
    substitute (K1's f_r3 #24, FL blown, FR stuck, 117 km/h, panic pedal: RL 80 bar against the substitute RR's 65,
    yaw toward FL 0.29 rad/s, refused at 2.4 s and spun: 19.585 m against the twin's 13.684).

    * Select-low on pressure: the blown side's rear is held at no more than the substitute's pressure (the braking
      rule's rear-pair hold, S_REAR_CAP, functions/esp.py: held at the level, dumped above it by > 1 bar; ABS's own
      hold/dump win), so the rear pair's moment points away from the blown side, as the compensation intends.
    * Yaw limitation (as K2's rule for the blown side's front, the ESP's GMA thresholds; no new number): while the yaw
      error toward the blown side (steered reference) exceeds esp.yaw_dump_rate, the blown side's rear is released -
      except in a curve steered toward the blown side (steered reference beyond the yaw dead band, the gate of the
      braking rule's lock floor) or with the sideslip phase-plane state outside the stable region (``phase_plane_
      unstable``): there the car already rotates on a saturated rear axle, releasing the inner rear leaves the outer
      rear alone braked and the car slid on almost unbraked until the refusal (measured, findings L2: f_r11 #24 8.599
      -> 18.564 m without the curve gate, f_r41 #459 13.343 -> 14.223 m without the phase-plane gate); the
      select-low still holds it there.
    * Value 2 (session m, tire_blowout_findings.md M7): the curve gate's premise checked - it holds only when the yaw
      error toward the blown side was already beyond esp.yaw_dump_rate at the first braking period of the LIMITED
      episode (S_M7_ERR0: a rotation under way before the pair braked, f_r11 #24: 0.168 rad/s). A rotation that grows
      under the pair's own braking (f_r41 #32: 0.02 rad/s at the pedal, refused and spun with the gate, 11.370 m vs the
      twin's 7.281; 7.393 m released) is the pair's moment: the steered reference already carries the curve."""
    w = b + 2  # the rear on the blown side
    if braking < 0.5:
        return
    # the curve gate: in a curve steered toward the blown side the inner rear is held, not released
    curve_ok = not curve_toward_blown_side(b, r_ref, p)
    if p.blowout_compensation_front_substitute_rear_flag > 1.5:
        # (value 2, M7) the gate's premise checked: a rotation already under way when the rear pair began to brake -
        # the yaw error toward the blown side (net of the steered reference) beyond esp.yaw_dump_rate at the first
        # braking period of this LIMITED episode. A rotation that grows only under the pair's braking is the pair's
        # own moment (both fronts unbraked, the rear axle braked on its own) and the yaw limitation releases it
        if st[S_M7_SET] < 0.5:
            st[S_M7_ERR0] = toward_blown_side(b, yaw_err)
            st[S_M7_SET] = 1.0
        curve_ok = curve_ok or st[S_M7_ERR0] <= p.esp_yaw_dump_rate_radps
    if (toward_blown_side(b, yaw_err) > p.esp_yaw_dump_rate_radps
            and curve_ok
            and not phase_plane_unstable(st[S_BETA_EST], st[S_BETA_DOT], p)):
        requests[w] = Q_RELEASE
    else:
        st[S_REAR_CAP] = max(p_est[tg], 0.0)  # select-low on pressure: at most the substitute's level


@nb.njit(cache=True, nogil=True, error_model="numpy")
def own_stuck_front(st, b, tg, yaw_err, p_est, p_mc, requests, p, r_curve=0.0, v_ref=0.0):
    """``own_stuck_front_flag`` (0 = the code before; tire_blowout_findings.md L8, session l): a blown FRONT whose OWN
    inlet valve is diagnosed stuck closed, compensated on the other front (BUILD/HOLD) while the driver brakes. The
    blown wheel then carries no brake in the car WITHOUT the function either (the driver's pressure never reaches it):
    the paper's release (P7) has nothing to remove, and the braking rule's premises - the compensating front takes its
    own driver demand on top of the drag balance because "the blown wheel's own demand is lost" (braking_share_frac),
    and the balance is the floor whatever the yaw - rest on a release the fault has already made in both cars. The
    driver's pressure on the other front is then already a counter-brake no wheel matches (b_f*F_opp(p_mc) against
    the flat's drag b_f*D, eqs. 22-25).

    * Yaw floor: while the yaw error (steered reference) points AWAY from the blown side beyond the closed-loop dead
      band (yaw_deadband, the braking rule's own gate), the compensating front goes down to the driver's pressure (the
      car without the function: not below it - a braking driver's wheel is the driver's and ABS's), not to the
      balance: S_P_BRAKE = p_mc, released (Q_RELEASE) while more than 1 bar above it. Within the dead band or toward
      the blown side the braking rule's target stands.
    * Rear pair (value 1; value 2 = the yaw floor alone): select-low on pressure when the braking rule sets no rear cap (no measured friction):
      the higher rear held at no more than 1 bar above the lower (S_REAR_CAP; the ESP's rear select-low, functions/
      esp.py, as HBA's pump build does it before a detection, hba_rear_select_low_flag) - the X-split pump lifted the
      blown front's circuit's rear 17-24 bar above the other (f_r41 #374, #29)."""
    if st[S_REAR_CAP] < 0.0 and p.blowout_compensation_own_stuck_front_flag < 1.5:
        st[S_REAR_CAP] = max(min(p_est[2], p_est[3]), 0.0) + PRESSURE_MARGIN_PA
    floor = max(p_mc, 0.0)
    if p.blowout_compensation_own_stuck_understeer_flag > 0.5 and curve_toward_blown_side(b, r_curve, p):
        # (own_stuck_understeer_flag, session o O8) the curve turns toward the blown (inner) front (the steered curvature
        # at the detection speed, r_curve, beyond the dead band) and the yaw falls short of the steered reference beyond
        # the dead band: understeer. The compensating front is the OUTER front, the
        # wheel that carries the curve with the inner tire flat; an ESP answers understeer under braking by lowering the
        # front's brake slip (more lateral force), never by braking the outer front (van Zanten SAE 2000-01-1633; Bosch
        # Automotive Handbook, ESP). The driver's pressure is no floor here: the ABS-held level is itself the over-brake
        # (fright_r41 #169: FL ABS-held at 40.7 bar under a 72-bar master, straight on in a right curve). Released
        # (Q_RELEASE, ABS re-builds once the gate closes) while the shortfall lasts.
        floor = 0.0
        if p.blowout_compensation_own_stuck_understeer_flag > 1.5 and st[S_GB_U0] > 1.0:
            # (value 2) the shortfall judged as path curvature too, at the detection speed (as r_curve): yaw_err *
            # u_det / u. A fixed yaw-rate dead band shrinks the curvature it tolerates as the car stops (#169 at 10 m/s:
            # 0.011 rad/s short = 75 % of the steered curve, inside the 0.0175 band, FL ABS-held at 42 bar)
            yaw_err = yaw_err * st[S_GB_U0] / max(v_ref, 1.0)
    if toward_blown_side(b, yaw_err) < -p.blowout_compensation_yaw_deadband_radps:
        if st[S_P_BRAKE] > floor:
            st[S_P_BRAKE] = floor
        if p_est[tg] > floor + PRESSURE_MARGIN_PA:
            requests[tg] = Q_RELEASE


@nb.njit(cache=True, nogil=True, error_model="numpy")
def heading_return_reference(steer_rad, speed_mps, speed_det_mps, p):
    """(reject_heading_return_flag 2, session j J7) The heading return's steered reference yaw rate: the path curvature
    the linear single-track model gives the measured road-wheel angle at the speed of the DETECTION,
    delta/(l + K*u_det^2), times the present speed. ``reference_yaw_rate`` uses the present speed in the understeer
    term K*u^2: with the steering held, its path curvature tightens as the braking car slows (SUV: x1.38 from 31 to
    20 m/s, x1.57 to 15 m/s) - a tighter path nobody steered, which a braking car (its understeer grows under braking:
    load to the front, the front tyres' force spent longitudinally) does not follow. Regulating the caused heading
    against it turned the car into the curve by the reference's own drift (lead fa_cau_signed #40, FR named, 650 m left
    curve, 112 -> 56 km/h: the car without the function yaws 3.0 deg below it by 5 s; J5's rule held the function car
    at it: 3 deg inside the twin's heading, 0.133 m beyond the inner marking). Assumed: the curvature asked at the
    alarm is the driver's, the change of the understeer term with speed afterwards is not (the driver's steering
    changes still count, through delta)."""
    if speed_det_mps <= 1.0:
        return reference_yaw_rate(steer_rad, speed_mps, p)
    return reference_yaw_rate(steer_rad, speed_det_mps, p) * speed_mps / speed_det_mps


@nb.njit(cache=True, nogil=True, error_model="numpy")
def heading_return_wheel(b, away):
    """(reject_heading_return_flag) The front wheel whose release turns the car back: on the side the car turned
    toward - opposite the named wheel b if it turned away from b (``away``; a release of b and a build opposite both
    yaw the car that way), on b's side if it turned (overshot) toward b."""
    if away:
        return OPPOSITE[b] if b < 2 else _substitute(b)
    return b if b < 2 else b - 2


@nb.njit(cache=True, nogil=True, error_model="numpy")
def heading_return_kick_seen(st, toward, p):
    """(``heading_return_own_yaw_flag``, session l L5; 0 = the code before: always True) May ``reject_heading_return``
    arm at this rejection? Its premise (J5) is a heading the FUNCTION's release + build turned the car by; S_GB_R0, the
    yaw error toward the named wheel at the detection, is the car's own (before any action). ``toward`` = the yaw error
    toward the named wheel now (at the rejection).

    Value 1: not if the car's own yaw error at the detection was already beyond the plausibility threshold away from the
    named wheel (toward(R0) < -abort_yaw_rate): the detection is then rejected in its first judged period, before any
    pressure of the function acts - the implausible yaw is the car's (lead fa_r11 #108: a braking car understeering out
    of a 650 m curve, R0 -2.83 deg/s, rejected 5 ms after the detection with FL 31.9 -> 32.0 bar; the rule then held the
    car's yaw error at -2.3 .. -2.8 deg/s below the steered reference for the rest of the stop by releasing the inner
    front FL 32 -> 5 bar: 4.03 m beyond the outer marking vs 2.39 m without the function).
    Value 2: see ``heading_return_toward_reference`` (arming as at 0)."""
    v = p.blowout_compensation_heading_return_own_yaw_flag
    if v < 0.5 or v > 1.5:
        return True
    return st[S_GB_R0] >= -p.blowout_compensation_abort_yaw_rate_radps


@nb.njit(cache=True, nogil=True, error_model="numpy")
def heading_return_own_restricted(st, p):
    """(``heading_return_own_yaw_flag``) Does the toward-the-reference restriction (values 2-5) apply to this armed heading
    return? Values 2, 3, 4: always. Value 5 (review RL1, session l): only when the car's own yaw error at the detection
    (S_GB_R0, before any action of the function) was already beyond the plausibility threshold abort_yaw_rate away from
    the named wheel - the rejection is then the car's own yaw, not a kick of the function's (lead fa_r11 #108: R0 -2.83
    deg/s, rejected 5 ms after the detection; L5's search s11 #238: -2.24 deg/s, 5 ms): there is no caused heading to give
    back and the rule may only bring the yaw rate TO the steered reference. Otherwise (the function acted: J5's premise,
    fa_cau #25, fa_r11 #98) J5/J7's heading return is left as it was (value 0), since giving a heading back needs a yaw
    rate past the reference. No new threshold (value 1's test, abort_yaw_rate). 0/1: never."""
    v = p.blowout_compensation_heading_return_own_yaw_flag
    if v < 1.5:
        return False
    if v > 4.5:
        return st[S_GB_R0] < -p.blowout_compensation_abort_yaw_rate_radps
    return True


@nb.njit(cache=True, nogil=True, error_model="numpy")
def heading_return_toward_reference(w, yaw_err, p):
    """(``heading_return_own_yaw_flag`` 3 shipped / 2 candidate, session l L5; 0/1 = the code before: True) May ``reject_heading_return``
    release front ``w``? Not when the car's yaw error against the rule's steered reference (``yaw_err``, measured minus
    ``heading_return_reference``, left +) already lies beyond the closed-loop dead band yaw_deadband in the direction
    the release turns the car (releasing a left wheel yaws the car right): an ESP's yaw control brakes single wheels to
    bring the car's yaw rate TO the driver's reference (van Zanten, Bosch ESP Systems: 5 Years of Experience, SAE
    2000-01-1633), never further from it. At fa_r11 #108 the rule released the inner front FL of a 650 m left curve with
    the car 2.3-2.8 deg/s below the reference (understeering out of the curve)."""
    if p.blowout_compensation_heading_return_own_yaw_flag < 1.5:
        return True
    turn = -1.0 if w % 2 == 0 else 1.0  # FL/RL released: the car yaws right (-)
    if p.blowout_compensation_heading_return_own_yaw_flag > 2.5:
        return yaw_err * turn <= 0.0  # (values 3 (shipped), 4, 5: no dead band - only releases that turn the car toward it)
    return yaw_err * turn <= p.blowout_compensation_yaw_deadband_radps


@nb.njit(cache=True, nogil=True, error_model="numpy")
def reject_heading_return(st, mode, braking, yaw_rate, v_ref, p_est, requests, p, dt):
    """``reject_heading_return_flag`` (0 = seeded defect = the code before: after a rejected detection the heading its
    release + build made stays). After a single-source detection of a healthy wheel is rejected while the driver brakes,
    the function takes back the heading it turned the car by: S_GB_PSI, the integral of the yaw error toward the named
    wheel NET of its value at the detection (a constant gyro offset and the car's own yaw error before the function
    acted cancel) - from the detection, continued after the rejection (the braking car near its friction limit has
    little yaw damping: the yaw rate the kick left persists, and held steering never corrects it). A heading controller
    on that integral, acting only by RELEASING a front wheel below the driver's / ABS pressure (never above what the
    pedal asks): the demanded yaw rate back is the heading over the 2 % settling time of the ECU's linear yaw mode
    (``settling_time_s``: a first-order return no faster than the car's yaw mode), at most the plausibility threshold
    abort_yaw_rate (the rate this function itself treats as a disturbance); short of the demand by more than the
    closed-loop dead band yaw_deadband the front wheel on the side the car turned toward is released (Q_RELEASE), beyond
    it by more than the band the other front (the overshoot is the rule's own), inside it both are the driver's and
    ABS's (Q_NONE). The release goes down to the pressure difference to the other front whose moment removes the rate
    error in one yaw-mode time constant (a quarter of the settling time, as front_spin_keep_arrest): I_z*|e|/tau through
    eq. 28 - a proportional moment, not a full dump (a full dump of a 40 bar front limit-cycled both fronts: lead fa_cau
    #25 speed at 5 s 11.1 vs 7.9 m/s). Runs while the detection stays rejected (mode REJECTED), the pedal is on and the
    car is above the function's minimum speed; a
    first version that ended at the heading's zero crossing left the yaw rate it had made (the car carries it: 0.62 m
    the other way).

    Flag 2 (shipped, session j J7; 1 = J5's rule above): the yaw error is taken against ``heading_return_reference``
    (the understeer term kept at the detection's speed), not against ``reference_yaw_rate`` - with the wheel held the
    latter's path tightens as the car slows and the rule turned the car into the curve by that drift."""
    bb = int(st[S_GB_B])
    if mode != REJECTED or braking < 0.5 or bb < 0 or v_ref < p.blowout_compensation_min_speed_mps:
        # (and below the function's minimum speed, as BUILD/HOLD -> ENDED: the baseline is a yaw error at speed - a
        # stopped car read -baseline and the rule released a held front 139 -> 1 bar at standstill, fa_nw3 #1)
        st[S_GB_ON] = 0.0
        return
    y = toward_blown_side(bb, yaw_rate) - st[S_GB_R0]
    st[S_GB_PSI] += y * dt
    t_s = settling_time_s(v_ref, p)
    r_max = p.blowout_compensation_abort_yaw_rate_radps
    y_d = min(max(-st[S_GB_PSI] / t_s, -r_max), r_max)
    e = y - y_d
    db = p.blowout_compensation_yaw_deadband_radps
    if abs(e) <= db:
        return
    w = heading_return_wheel(bb, e < 0.0)
    if p.blowout_compensation_heading_return_abs_flag > 0.5 and st[S_ABS_ACTIVE + w] > 0.5:
        # (heading_return_abs_flag, session o O6; 0 = the code before) no release of a front ABS holds at its lock
        # level (a hold or dump in the last 0.3 s, spec 4.3, S_ABS_ACTIVE): the release's moment is eq. 28's
        # b*K_b*dp/R only while the tire is in its linear region; at the lock level the tire's force is on the friction
        # circle and a release turns brake force into LATERAL force (Kamm circle) - in a curve the freed front's
        # cornering force turns the car INTO the curve, against the yaw the rule asks for (O6: fkR #26, a real FR flat
        # rejected by the yaw, 118 km/h mu 0.34 1000 m right curve: the rule released FL then FR, the car spun
        # right, 18.8 m off vs the twin's 0.97 m; findings O6). The wheel stays the driver's and ABS's.
        return
    restricted = heading_return_own_restricted(st, p)
    if restricted and not heading_return_toward_reference(w, yaw_rate, p):
        return
    # the pressure difference to the other front that removes the rate error in one yaw-mode time constant
    # (I_z*|e|/tau, eq. 28's moment-to-pressure of the front axle, ECU nominal data): released down to it, then the
    # driver's and ABS's again (a release only: never above what the pedal asks)
    e_m = abs(e)
    if restricted and p.blowout_compensation_heading_return_own_yaw_flag > 3.5:
        # (heading_return_own_yaw_flag 4 and 5, review RL1) the release turns the car TOWARD the steered reference (value 3's
        # gate) and is sized to the rate error to that reference, not beyond it: a release sized to the rule's own
        # target (S_GB_R0 + the return rate, up to abort_yaw_rate + the baseline past the reference) crosses the
        # reference and the released front's ABS re-build carries the moment on after value 3's gate closes
        e_m = min(e_m, abs(yaw_rate))
    dp = required_pressure_pa(p.body_yaw_inertia_kgm2 * e_m / (0.25 * t_s), p.body_wheel_radius_m,
                              0.5 * p.chassis_front_track_m, p.brakes_front_gain_nm_per_pa)
    if p.blowout_compensation_heading_return_line_flag > 0.5:
        # (heading_return_line_flag, session k K3; 0 = the code before: A_P_EST of both fronts) the released front and
        # the front it is compared with on ONE estimate, the line-lag A_P_LINE (esp.lock_level_line_flag's): after the
        # rejection the comparison front is often the re-applied rejected front, whose A_P_EST in mode N is the master's
        # pressure at once (fa9: 100-119 bar while the wheel held 51-53) - the rule never released. And a braking bound:
        # the released front never below half the other front's pressure, so the front axle keeps >= 0.75 of its brake
        # force (UN R13-H Annex 6 para 5.2: an anti-lock car's adhesion utilisation epsilon >= 0.75; the rears untouched)
        p_w = st[S_P_LINE + w]
        p_o = st[S_P_LINE + OPPOSITE[w]]
        if p.blowout_compensation_heading_return_line_flag > 1.5:  # (value 1: the line estimate, no bound - RJ2's copy)
            dp = min(dp, HEADING_RETURN_AXLE_KEEP_FRAC * p_o)
        if p_w > p_o - dp:
            requests[w] = Q_RELEASE
    elif p_est[w] > p_est[OPPOSITE[w]] - dp:
        requests[w] = Q_RELEASE


@nb.njit(cache=True, nogil=True, error_model="numpy")
def blown_front_hold(st, b, tg, mode, braking, yaw_rate, r_ref, requests, p):
    """The blown FRONT wheel, the inner front of a turn steered toward it, is held at its present (ABS) pressure instead
    of released (``blown_front_hold_flag``, 0 = seeded defect = always released; tire_blowout_findings.md X2, lead random 41 b512
    #273) while: the driver brakes; the compensation runs on the other front (BUILD/HOLD/LIMITED); that front is at
    its ABS limit (ABS active on it - a hold or dump in the last 0.3 s, spec 4.3, S_ABS_ACTIVE from functions/esp.py;
    with ``braking_lock_keep_flag`` also a lock level ABS found on it and still kept, S_LOCK_P of braking_lock_floor);
    the steered reference yaw rate (``reference_yaw_rate``) points toward the blown side by more than the closed-loop
    dead band (a curve toward it); and the measured yaw rate is not above that reference toward the blown side.

    Why: the paper releases the blown wheel (eqs. 26-28, F_b = 0) inside a balance in which the other front takes the
    counter-force p_w: M_z = b_f*(F_b + D - F_opp) = 0. With the driver's pressure already holding that front at its
    lock level, ABS caps it (the arbitration gives BUILD/HOLD way to ABS): the function has no authority left on the
    front axle, and the release is the only moment it makes - b_f*K_b*p_b/R away from the blown side, of a size set
    by the pedal, not by the blowout. In a turn toward the blown side that moment points out of the turn. An ESP
    brakes the outer front (a moment out of the turn) against oversteer and the inner rear (a moment INTO the turn)
    against understeer (van Zanten, Bosch ESP Systems: 5 Years of Experience, SAE 2000-01-1633; Bosch Automotive
    Handbook, ESP); derived from that, not stated there: at or below the steering's demand no brake force is taken off
    the inner front. So the
    sign of the yaw deviation decides: above the reference (the drag turning the car in) the release goes on as
    before, otherwise the blown front keeps what the driver and ABS give it, as without the function. On a straight
    road (no inner wheel) the paper's release stands (the drag is a pure disturbance; holding there cost #101 1.99 ->
    3.31 m). NOT a pressure hold (review RG, session g): a flat front the function already released to 0-1.4 bar is
    re-applied by Q_HOLD - 0 -> 44-60 bar within 5-10 ms, the driver's master pressure (197 bar at random 37 #7)
    through the open inlet (W_B with the USV check valve, or W_N; plant/brakes/esp_unit.py), then ABS-dumped; that
    re-apply is the rule's benefit at #273 and, cycling with the yaw around the reference, its cost (random 37 b64 #7
    0.096 -> 1.003 m, none 10.56; random 17 #51 0.855 -> 2.277, none 9.57); a false FL TPMS alarm in a left curve
    is rejected up to 3.5 s later (the held healthy wheel gives the yaw no
    release signature). Held = Q_HOLD: the function adds no build and takes nothing off; ABS keeps its hold, dump and
    pulsed re-build from the master of the wheel (BLOWOUT_ARBITRATION row HOLD), as without the function - a flat wheel
    ABS had dumped before the detection is re-built by it too (random 3 fl/fr-braking b64 #53: 1.2 -> 34-46 bar,
    0.49 -> 1.94 m, none 8.36; capping the re-build at the detection's pressure fixed that but re-opened braking 5
    #124 and 13 #45, 2.04 / 2.20 m vs none 1.34 / 2.00: not done)."""
    if (braking < 0.5 or b < 0 or b >= 2 or tg < 0 or tg >= 2 or tg == b
            or not (mode == BUILD or mode == HOLD or mode == LIMITED)):
        return
    if st[S_ABS_ACTIVE + tg] < 0.5 and not (p.blowout_compensation_braking_lock_keep_flag > 0.5
                                            and p.blowout_compensation_braking_lock_floor_flag > 0.5
                                            and st[S_LOCK_P] > 0.0):
        # (braking_lock_keep_flag, 0 = seeded defect = ABS activity only) a compensating front whose lock level ABS
        # found is kept (S_LOCK_P, braking_lock_floor: held at or below the floor) is at its limit: the braking rule's
        # floor holds it below that level, and that is why ABS is quiet on it (tire_blowout_findings.md H8: false FL alarm, FR
        # held at 0.8 x lock, ABS quiet 0.3 s later, the healthy FL let go three times: 0.856 m, 0.744 m with the rule)
        return
    if not curve_toward_blown_side(b, r_ref, p):
        return  # not a turn toward the blown side
    toward = toward_blown_side(b, yaw_rate)
    if toward > 0.0:
        return  # yawing toward the blown side beyond the steering's demand: the release answers it
    requests[b] = Q_HOLD


@nb.njit(cache=True, nogil=True, error_model="numpy")
def understeer_rule(st, b, tg, mode, braking, r_ref, yaw_rate_meas, p_est, requests, p, dt=0.005, v_ref=0.0):
    """Blown FRONT wheel on the inside of the turn the driver steers, the car understeering (``understeer_flag``, 0 =
    seeded defect = the code before; tire_blowout_findings.md R3 and X, tire_blowout.md open item 1). Acts in HOLD on the other
    front wheel, while the driver does not brake, once the tire-capacity rule has measured a friction below the nominal
    on that wheel (S_CAP_LATCHED: a saturating front axle), when the steering reference (``reference_yaw_rate``) points
    toward the blown side by more than the dead band (yaw_deadband_deg_per_s) and the measured yaw rate falls short of
    it by more than the dead band: understeer, yaw rate below the steering's demand. ESP practice answers understeer
    with a yaw moment INTO the turn (the inner rear wheel braked) and brakes the outer front only against oversteer (van
    Zanten, Bosch ESP Systems: 5 Years of Experience, SAE 2000-01-1633; Bosch Automotive Handbook, ESP); the blown inner
    front's drag is such a moment, and the compensating OUTER front's brake force takes friction circle from the front
    axle that carries the curve with one tire flat. While it lasts the target is lowered to the wheel's present
    pressure (never below the pressure at detection S_P_START) and the added pressure dumped; within the dead band the
    lowered target is held; once the car turns toward the blown side MORE than the reference by the dead band (the
    drag's moment now exceeds what the curve asks) the target before the lowering (S_US_PLAN) is restored and the ESP
    re-builds it: a yaw-rate loop around the steering reference between the pressure at detection and the paper's
    balance. Measured (session f): without the capacity evidence the build's over-compensation dip on a dry curve
    lowered the target (shipped blowout_lf_80kph_curve 0.58 -> 1.28 m); acting while braking made random 43 #24
    0.65 -> 1.64 m (braking: the braking rule and its own yaw feedback govern from the present balance); a latched
    lowering (no restore) cost fixed-steering curve points up to 3 m of their benefit; a 0.25 s persistence before acting
    (against the build's over-compensation dip) made F6 #16 0.37 -> 1.06 m and random 3 #19 1.12 -> 1.86 m.
    ``understeer_persist_flag`` (0 = seeded defect = capacity evidence required): a shortfall lasting the 2 % settling
    time of the ECU's yaw mode (``settling_time_s``, S_US_SHORT_S) counts as the evidence too - the build's dip is that
    mode's transient, a shortfall outlasting it is the steady response (RG2's targeted 19 #66 / 71 #49: FR 42-49 bar at
    6-7 % slip, capacity never latched, 1.77 / 1.58 m vs none 1.11 / 1.36; with it 0.54 / 0.64 m); a lowering made on
    the persistence alone is restored only once the yaw has exceeded the reference by the dead band for the same time
    (S_US_OVER_S: restored on the first overshoot sample, FR was re-built 0.2 s after the lowering and #66 stayed at
    1.24 m). Shipped blowout_lf_80kph_curve (fixed steering): 3-s deviation 0.460 -> 0.312 m, run max 0.581 -> 0.680 m
    (none 6.63); its checks unchanged. ``understeer_restore_settled_flag`` (0 = seeded defect = restored only beyond the
    dead band): that restore's evidence is the yaw above the reference without the dead band for the settling time -
    inside the dead band lf80's lowering was held while the car turned 0.02 rad/s more than the lane (1.009 m at
    standstill, out of the lane; with it 0.153 m, run max 0.059 m; tire_blowout_findings.md RH2)."""
    # (understeer_braking_flag, 0 = the code before: the rule rests while the driver brakes; session l L4, fb5 #164) the
    # shortfall is timed across the pedal and the rule acts under it too, the braking rule then keeps the lowered balance
    brk_ok = p.blowout_compensation_understeer_braking_flag > 0.5
    if (brk_ok and p.blowout_compensation_understeer_braking_flag > 1.5 and braking > 0.5
            and st[S_US_SHORT_S] <= 0.0 and st[S_US_LIMITED] < 0.5):
        # (understeer_braking_flag 2, session m M3) only a shortfall already being timed - or a lowering already made -
        # WITHOUT the pedal carries across it; no fresh start under the pedal (value 1 started one there too)
        brk_ok = False
    if b < 0 or b >= 2 or tg != OPPOSITE[b] or mode != HOLD or (braking > 0.5 and not brk_ok):
        st[S_US_SHORT_S] = 0.0  # (understeer_persist_flag) the shortfall is timed in HOLD without the pedal only
        st[S_US_OVER_S] = 0.0
    if b < 0 or b >= 2 or tg != OPPOSITE[b] or mode != HOLD:
        return
    if braking > 0.5 and not brk_ok:
        return  # the driver brakes: the braking rule (its own yaw feedback on the driver's share) governs from the present
        #   balance, lowered or not
    db = p.blowout_compensation_yaw_deadband_radps
    ref_in = toward_blown_side(b, r_ref)
    err_in = toward_blown_side(b, yaw_rate_meas) - ref_in  # + = turning toward the blown side more than asked
    short = ref_in > db and err_in < -db
    evidence = st[S_CAP_LATCHED] > 0.5
    if p.blowout_compensation_understeer_persist_flag > 0.5:
        # (understeer_persist_flag) a shortfall that outlasts the 2 % settling time of the ECU's single-track yaw mode
        # (settling_time_s) is the car's steady response, not the build's transient over-compensation dip (which the
        # capacity evidence was there to keep out): the drag balance the ECU planned exceeds the blown wheel's moment
        # the car actually needs on this road, or the front axle saturates without the compensating wheel's own slip
        # showing it (lead's targeted random 19 #66 / 71 #49: FR 42-49 bar at 6-7 % slip, capacity never latched,
        # yaw 0.04-0.09 rad/s short of the follower's reference for 3 s)
        t_s = settling_time_s(v_ref, p)
        st[S_US_SHORT_S] = st[S_US_SHORT_S] + dt if short else 0.0
        over_db = db
        if (p.blowout_compensation_understeer_restore_settled_flag > 0.5 and st[S_US_LIMITED] > 0.5
                and st[S_CAP_LATCHED] < 0.5):
            # (understeer_restore_settled_flag) a lowering made on the persistence alone is taken back on the mirror
            # evidence: the yaw above the steering reference (no dead band) for the same settling time. The dead band
            # keeps single noisy samples out; a sign that lasts the yaw mode's settling time is the steady response.
            # Within the dead band the lowered target was held for good: with the wheel held at the entry angle the
            # reference's curvature delta/(l*(1 + K*u^2)) rises above the lane's 1/R as the car slows (understeer
            # gradient K > 0), and at 0.012-0.018 rad/s above the reference (db 0.0175) the car turned 0.02 rad/s
            # more than the lane for 2 s (shipped blowout_lf_80kph_curve run to standstill: 1.009 m, out of the
            # lane, vs 0.606 m before understeer_persist_flag; tire_blowout_findings.md RH2)
            over_db = 0.0
        st[S_US_OVER_S] = st[S_US_OVER_S] + dt if err_in > over_db else 0.0
        if st[S_US_SHORT_S] >= t_s - 1e-9:
            evidence = True
        if (st[S_US_LIMITED] > 0.5 and st[S_CAP_LATCHED] < 0.5 and err_in > over_db
                and st[S_US_OVER_S] < t_s - 1e-9):
            # a lowering made on the persistence alone is restored on the same evidence: the yaw's swing past the
            # reference after the dump is the same yaw mode's transient (at 19 #66 the restore on the first overshoot
            # sample re-built FR to 43 bar 0.2 s after the lowering and the shortfall came back)
            return
        if over_db < db and err_in > over_db and st[S_US_LIMITED] > 0.5:
            # (understeer_restore_settled_flag) the excess has lasted the settling time: the balance back
            understeer_restore(st, p, dt)
            return
    if short and evidence:
        if st[S_US_LIMITED] < 0.5:
            st[S_US_PLAN] = st[S_P_REQ]
        st[S_US_LIMITED] = 1.0
        st[S_P_REQ] = max(min(st[S_P_REQ], p_est[tg]), st[S_P_START])
        requests[tg] = Q_RELEASE if p_est[tg] > st[S_P_START] + PRESSURE_MARGIN_PA else Q_HOLD
    elif st[S_US_LIMITED] > 0.5 and err_in > db:
        # turning toward the blown side beyond the reference: the balance before the lowering back (re-built by the ESP)
        understeer_restore(st, p, dt)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def understeer_restore(st, p, dt):
    """The understeer rule's restore: the balance before the lowering back (S_US_PLAN; the ESP re-builds the wheel)."""
    st[S_P_REQ] = max(st[S_US_PLAN], st[S_P_REQ])
    st[S_US_LIMITED] = 0.0
    if p.blowout_compensation_understeer_cap_freeze_flag > 0.5:
        # (understeer_cap_freeze_flag) the filter window still holds the held wheel's samples: the capacity evidence
        # counts again only after a fresh window (as the rear slip limit's S_SLIP_HIGH_S), not from the hold's
        st[S_LOW_S] = -WS_WINDOW_N * dt


@nb.njit(cache=True, nogil=True, error_model="numpy")
def braking_rule(st, b, tg, mode, braking, a_x, a_y_ref, yaw_rate, p_mc, p_est, p, r_ref=0.0, a_y_meas=0.0,
                 v_ref=0.0):
    """One rule for a FRONT blowout while the driver brakes (``braking_rule_flag``, 0 = seeded defect = the rules
    before; issue #10, falsifier random seed 7 #15/#16). Yaw-moment balance of the four brake forces with the blown
    front wheel unbraked (it only drags, D = mu_blow*F'_z, eqs. 22-25): M_z = b_f*(D - F_opp) + b_r*(F_rl - F_rr)
    (blown left; mirrored for the right). Its terms:

    * compensating front wheel (b_f*(D - F_opp)): target = the drag balance p_w of eqs. 26-28 as planned and limited
      (S_P_REQ, the tire-capacity rule included) plus ``braking_share_frac`` x the driver's pressure, the share at most
      up to the friction circle of the wheel at the measured friction with its share of the front lateral force for
      the steered path (F_x <= sqrt((mu*F_z)^2 - F_y^2), F_y = m*|a_y|*l_r/l shared with the flat tire by cornering
      stiffness); never below the balance. With a measured friction (S_MU_MEAS) the cap is that measured
      longitudinal capacity mu_meas*F_z (``front_circle_measured_flag``, 0 = seeded defect = the circle at mu_meas): the
      capacity rule's pure-longitudinal Dugoff inversion on a cornering wheel already reads the friction left for F_x
      next to F_y (combined slip), the circle subtracted F_y twice (random 7 #16: 12.5 bar vs the twin's 31, 0.312 ->
      0.129 m, none 0.225). The share is a yaw moment away from the blown side (b_f*share*K_b*p/R):
      it is taken only while the measured yaw (relative to the steered reference) does not point away from the blown
      side; yawing away within the closed-loop dead band (yaw_deadband_deg_per_s) it is held where it is, beyond it
      the wheel goes back to the balance (the true drag D is unknown to the ECU: the yaw rate tells whether F_opp
      already exceeds it; the share taken open-loop yawed a wet-curve car 1.1 m outward). After an ABS dump it
      re-builds (functions/esp.py) to no more than its pressure at the dump's start (S_P_PREDUMP, ABS's lock
      level), not to the plan's lowered no-brake target (a noise-triggered dump held RF at ~7 bar for 1.5 s while
      the rears took the driver's 30-40 bar); that ceiling ends when ABS lets the wheel go (build_idle, no hold or
      dump for abs_idle_time_s: no lock level is known any more).
    * rear pair (b_r*(F_rl - F_rr)): one cap for both (the lower of the two, as the ESP's select-low, so the pair adds
      no moment): the friction circle sqrt((mu*F_z)^2 - F_y^2) with its half of the rear lateral force at the measured
      friction (``wheel_circle_limit_mu``, ``rear_circle_flag``; 0 = seeded defect = the Dugoff linear-region force,
      ``wheel_linear_limit_mu``, the f(H) >= 1 - s boundary, about half the friction: in a 650 m curve at 108-118 km/h
      and mu 0.32-0.43 the curve's lateral force alone used it and 0-3 bar of the driver's 39 bar stayed on the intact
      rear axle, the car hardly slowed and drifted out of the curve, falsifier random seed 43 #24): with the front axle
      one wheel short the driver's uncapped rear pressure took the rear tires to 5-10 % slip on a wet curve and the car
      spun toward the blown side (random seed 7 #15). While ABS acts on the compensating front the pair is left to ABS
      (``rear_abs_limit_flag``), except in a curve toward the blown side (``rear_accel_circle_flag``): there the circle
      is taken at the friction the measured acceleration proves, max(mu_meas, sqrt(a_x^2 + a_y^2)/g).

    Friction: the lowest the tire-capacity rule measured on the compensating wheel before the pedal (S_MU_MEAS), else
    the ECU's nominal mu_estimate_frac; the rear cap acts only on a measured friction (without evidence of a slippery
    road the rear pair stays the driver's and ABS's: at the nominal 0.8 the linear cap made the shipped dry panic stops
    ~4 m longer). Loads: the ECU's (ecu_loads at the measured a_x, blowout transfer). Writes S_P_BRAKE and S_REAR_CAP
    (-1 when not acting); the ESP arbitration reads them."""
    st[S_P_BRAKE] = -1.0
    st[S_REAR_CAP] = -1.0
    if b >= 2 and p.blowout_compensation_rear_braking_flag > 0.5:
        rear_braking_rule(st, b, tg, mode, braking, p_mc, p_est, p)  # a REAR blowout (rear_braking_flag)
        return
    if braking < 0.5 or b < 0 or b >= 2 or tg < 0 or tg >= 2 or not (mode == BUILD or mode == HOLD or mode == LIMITED):
        st[S_P_PREDUMP] = -1.0
        st[S_REAR_OS_CAP] = -1.0
        st[S_LOCK_P] = -1.0
        st[S_LOCK_PREV] = -1.0
        st[S_LOCK_FALL] = 0.0
        return
    mu = st[S_MU_MEAS] if st[S_MU_MEAS] > 0.0 else p.blowout_compensation_mu_estimate_frac
    g0, g1, g2, g3 = blown_ecu_loads(b, a_x, p)
    gl = (g0, g1, g2, g3)
    r_w = p.body_wheel_radius_m
    fx_max = wheel_circle_limit_mu(tg, gl[tg], a_y_ref, mu, b, p)  # its friction circle next to its lateral share
    p_bal = st[S_P_REQ]
    if p.blowout_compensation_front_circle_measured_flag > 0.5 and st[S_MU_MEAS] > 0.0:
        # front_circle_measured_flag: the measured friction is the pure-longitudinal Dugoff inversion on a wheel that
        # carried its lateral share while measured (combined slip lowers F_x at the same slip): it is already the
        # friction left for F_x next to the curve's lateral force - the circle would subtract F_y a second time
        fx_max = mu * max(gl[tg], 0.0)
    p_circle = fx_max * r_w / p.brakes_front_gain_nm_per_pa
    if p.blowout_compensation_front_abs_limit_flag > 0.5 and st[S_MU_MEAS] > 0.0:
        # (front_abs_limit_flag, 0 = seeded defect = capped at mu_meas*F_z) the measured friction is a lower bound
        # (measured_mu_raise: what the wheel's readings prove, not its limit); a cap at it holds a compensating front
        # that was never measured at its limit below what ABS - which guards this wheel while the driver brakes
        # (functions/esp.py) - would allow. ABS is the limiter; the yaw gate below keeps the balance
        p_circle = 1.0e9
    p_full = max(p_bal, min(p_bal + p.blowout_compensation_braking_share_frac * max(p_mc, 0.0), p_circle))
    toward = toward_blown_side(b, yaw_rate)
    p_floor = p_bal  # the floor while the yaw points away from the blown side
    if p.blowout_compensation_braking_lock_floor_flag > 0.5:
        p_lock = braking_lock_floor(st, tg, p_bal, p_est, p)  # tracks the lock level every period
        if curve_toward_blown_side(b, r_ref, p) and (
                p.blowout_compensation_blown_front_hold_flag > 0.5
                or p.blowout_compensation_braking_lock_premise_flag < 0.5):
            # a curve toward the blown side: its inner front held, not released (blown_front_hold); (braking_lock_
            # premise_flag, 0 = seeded defect = whatever blown_front_hold_flag) without that hold the blown front is
            # released as the paper does and the balance's premise stands (tire_blowout_findings.md RH2 (c), H8)
            p_floor = p_lock
    if toward < -p.blowout_compensation_yaw_deadband_radps:
        st[S_P_BRAKE] = p_floor
    elif toward < p.blowout_compensation_yaw_deadband_radps:
        side_stop = p.blowout_compensation_blown_side_stop_flag > 0.5 and st[S_LIMIT_CODE] == LIMIT_BLOWN_SIDE
        if (p.blowout_compensation_stop_share_flag > 1.5 and toward < 0.0 and not side_stop
                and (int(st[S_SOURCES] + 0.5) & SRC_WS) != 0):
            # (stop_share_flag value 2, session o O9) value 1 narrowed to what the ECU measures: (a) only a detection
            # the wheel speeds confirm (S_SOURCES has the wheel-speed bit): a TPMS-only naming proves no drag on the
            # named wheel, the share then brakes the counter front against a wheel that may have none (false alarms
            # fa_r3 #20, far_r3 #61/#96; r41 #273); (b) the held front is raised to the DRIVER's pressure, not to the
            # balance plus the share: inside its dead band an ESP leaves the driver's braking alone (van Zanten, SAE
            # 2000-01-1633), i.e. the wheel gets what the pedal asks; a front already held above it (the balance alone
            # exceeding the pedal: f_r41 #326, 51 bar balance vs 21 bar pedal) stays held. fb5 #18: FR held 18-24 bar
            # against the driver's 55 -> 55 bar. Never above p_full (the rule's circle/ABS ceiling)
            st[S_P_BRAKE] = min(max(p_est[tg], p_floor, max(p_mc, 0.0)), p_full)
        elif side_stop or (p.blowout_compensation_stop_share_flag > 0.5 and p.blowout_compensation_stop_share_flag < 1.5):
            # (stop_share_flag, session o O7) the same for every blown front under the pedal: inside the dead band
            # the counter-brake front takes its share, not held where it last was (fb5 #18: FR frozen at 18-24 bar
            # against the driver's 55 for 8 s, a latch value set by one ESP period; findings O7)
            # (blown_side_stop_flag, session o O4) a blown FRONT whose side's REAR inlet is stuck (code 6, written by
            # blown_side_fault under the pedal): the paper's release of the blown front and the stuck rear leave the
            # blown side without any brake, so eq. 9 with F_rl = 0 makes this front and the free rear the car's only
            # brakes. Held where it is inside the dead band, the front stayed at the balance for the whole stop (t_r41
            # #474: FR 2.3 bar against the driver's 72 for 12 s, 1.7 m/s^2 vs the twin's 4.7, the car left the road
            # 8.4 s after the blowout). Inside the closed-loop dead band an ESP does not act on the driver's braking
            # (van Zanten, SAE 2000-01-1633; Bosch Automotive Handbook, ESP): the share is taken; beyond the dead
            # band away from the blown side the gate above still returns the wheel to the balance
            st[S_P_BRAKE] = p_full
        else:
            st[S_P_BRAKE] = min(max(p_est[tg], p_floor), p_full) if toward < 0.0 else p_full
    else:
        st[S_P_BRAKE] = p_full
    if st[S_MU_MEAS] > 0.0:
        f_rl, _ = wheel_linear_limit_mu(2, gl[2], a_y_ref, mu, b, p)
        f_rr, _ = wheel_linear_limit_mu(3, gl[3], a_y_ref, mu, b, p)
        if p.blowout_compensation_rear_circle_flag > 0.5:
            f_rl = max(f_rl, wheel_circle_limit_mu(2, gl[2], a_y_ref, mu, b, p))
            f_rr = max(f_rr, wheel_circle_limit_mu(3, gl[3], a_y_ref, mu, b, p))
        st[S_REAR_CAP] = min(f_rl, f_rr) * r_w / p.brakes_rear_gain_nm_per_pa
        if p.blowout_compensation_rear_abs_limit_flag > 0.5 and st[S_ABS_ACTIVE + tg] > 0.5:
            # (rear_abs_limit_flag, 0 = seeded defect = capped) the compensating front is at its ABS limit: the driver
            # asks more than the road gives. The measured friction is a lower bound read on that FRONT wheel (the
            # dump's force at the fade gain); a rear cap at it held the rears far below what their ABS allows (60 km/h
            # front panic stop: 8 bar, 0.18 kN each vs the twin's 33 bar, 0.84 kN). ABS is the rears' limiter (select-
            # low pair: no moment), the oversteer caps below still act
            st[S_REAR_CAP] = -1.0
            if (p.blowout_compensation_rear_accel_circle_flag > 0.5
                    and curve_toward_blown_side(b, r_ref, p)):
                # (rear_accel_circle_flag, 0 = seeded defect = no cap) a curve toward the blown side (the blown front
                # is the INNER one): the flat's diagonal load transfer unloads the OUTER rear, which carries the larger
                # share of the rear lateral force, and under the select-low pair it is the wheel ABS runs at its lock
                # slip (tire_blowout_findings.md I2: RR 10-18 % slip, 0.1-0.17 kN lateral vs 0.36-0.6 kN capped). Cap the pair at
                # the rears' friction circle (Kamm) at the friction the car's measured acceleration proves,
                # mu >= |a|/g = sqrt(a_x^2 + a_y^2)/g (|sum F_i| = m*|a| <= sum mu*F_z,i = mu*m*g), which rises with
                # the stop - not at the front wheel's lower bound alone. With the blown front OUTSIDE the turn the
                # select-low wheel is the inner rear and the loaded outer rear keeps its lateral reserve under ABS: a
                # cap there cost speed and no lateral force (I2: 20 of 22 worse points were such FR points)
                if p.blowout_compensation_rear_accel_bound_flag > 0.5:
                    # (rear_accel_bound_flag, 0 = seeded defect = |a|/g) the measured acceleration less what no
                    # friction of a tire carries: the air and rolling resistance and the blown rim's drag (review RI2:
                    # |a|/g read 0.558 / 0.486 for a road peak of 0.489 / 0.423 at R17_24 / BB29_3)
                    # the blown front's load at its most: the ECU's static + braking transfer before the flat's radius
                    # loss (eqs. 3-4) and the lateral transfer (it is the inner front here) take load off it
                    fz_b = ecu_loads(p, a_x)[b]
                    if p.blowout_compensation_rear_accel_bound_flag > 1.5 and toward_blown_side(b, a_y_meas) < 0.0:
                        # (2; 1 = RI2's bound = the code before) the gate is the STEERED curve; where the MEASURED
                        # lateral acceleration points away from the blown side that wheel is the OUTER one and its
                        # lateral transfer (eqs. 3-4, wheel_load_and_lateral_n) loads it: without it Z was no upper
                        # bound and mu read up to 4.5 % above the road's (review RI3, session i)
                        fz_b = max(fz_b, wheel_load_and_lateral_n(b, fz_b, a_y_meas, b, p)[0])
                    mu_acc = max(mu, accel_friction_lower_bound(a_x, a_y_meas, v_ref, fz_b, p))
                else:
                    mu_acc = max(mu, math.sqrt(a_x * a_x + a_y_meas * a_y_meas) / G_MPS2)
                c_rl = wheel_circle_limit_mu(2, gl[2], a_y_ref, mu_acc, b, p)
                c_rr = wheel_circle_limit_mu(3, gl[3], a_y_ref, mu_acc, b, p)
                st[S_REAR_CAP] = min(c_rl, c_rr) * r_w / p.brakes_rear_gain_nm_per_pa
    if p.blowout_compensation_rear_oversteer_flag > 0.5:
        rear_oversteer_cap(st, b, yaw_rate, p_est, p, r_ref, mode)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def braking_lock_floor(st, tg, p_bal, p_est, p):
    """The braking rule's floor for the compensating FRONT wheel while the yaw points away from the blown side
    (``braking_lock_floor_flag``, 0 = seeded defect = the drag balance S_P_REQ whatever ABS found): the balance, but
    never above ``braking_lock_floor_frac`` x the wheel's pressure when ABS last started a dump on it (S_LOCK_P).

    Why: the balance p_w of eqs. 26-28 is planned at the ECU's nominal friction for a RELEASED blown front (it only
    drags); on a wet road the compensating front reaches its lock level below it, and with the blown inner front held
    at the driver's/ABS level (blown_front_hold_flag) the drag it balances is not there. ABS's dump IS the measurement of
    that wheel's lock level (a dump from the slip or the wheel-deceleration threshold, spec 4.3: the brake torque has
    passed what the tire carries); a wheel cannot carry more than that. With the floor at the balance the accumulator
    re-built the wheel after every dump up to the lock level and beyond (the ESP's S_P_PREDUMP ceiling, when it is set at
    all, IS the lock level), so the outer front sat at its lock: slip 5.5-15 % against the twin's 3.4-7.7 %, its
    lateral force up to 40 % lower, and the car yawed away from the blown side beyond the dead band on the
    compensation's own moment (tire_blowout_findings.md G8/H3: lead's CMA-ES 2026 -n 200 cluster, FL, r650 toward FL, mu
    0.30-0.35). ABS practice is to re-apply after a dump to a fraction of the pressure at which the wheel locked and to
    increase it gradually from there (GM, Leppek, EP 0 380 882: re-apply to "a significant fraction" of that pressure;
    the fraction is braking_lock_floor_frac, assumed); here the
    re-build stops at that fraction and the wheel is held (the floor is a re-build limit, never a dump: a wheel above
    it is only not re-built) until ABS is quiet on it (no hold or dump for 0.3 s, S_ABS_ACTIVE, spec 4.3): the lock level
    is then forgotten and the floor is the balance again, as ABS forgets it (functions/esp.py build_idle) - with
    ``braking_lock_keep_flag`` (0 = seeded defect = that) only once the wheel is also above the floor + 1 bar (held at
    or below it, the floor is what keeps ABS quiet; tire_blowout_findings.md H8), and always when braking_rule stops. A dump is
    the ECU's pressure estimate falling by more than 1 bar in one period from at most the balance + 1 bar (the rule
    itself lowers a wheel only from above the balance, functions/esp.py); its start is the level. Only while the yaw
    points away from the blown side (the counter-moment already exceeds the drag): toward it the balance stands (a
    low, noise-made ceiling there spun the car, tire_blowout_findings.md Q4 / predump_slip_flag). And only in a turn steered
    toward the blown side (steered reference toward it beyond the dead band, the caller): there the blown INNER front is
    held at the driver's/ABS level (blown_front_hold), so the balance's premise, a released blown front that only drags,
    does not hold; on a straight road or with the blown wheel on the outside the paper's release stands and so does its
    balance (measured, tire_blowout_findings.md H3: the floor everywhere made 18 of 245 braking front points of session g's
    searches worse by 0.05-0.40 m, 15 of them straight-road or outer-front points, none a violation; restricted: 3)."""
    # (esp.lock_level_line_flag, 0 = the code before = A_P_EST) the level and the wheel compared with it on ONE estimate,
    # the line-lag one (A_P_LINE): the plant's wheel follows the source through the line lag tau_line (esp_unit row N),
    # while A_P_EST takes the source at once in N - a dump right after N stored the source, not the locking pressure
    p_now = st[S_P_LINE + tg] if p.esp_lock_level_line_flag > 0.5 else p_est[tg]
    p_prev = st[S_LOCK_PREV]
    keep = p.blowout_compensation_braking_lock_keep_flag > 0.5
    held = st[S_LOCK_P] > 0.0 and p_now <= p.blowout_compensation_braking_lock_floor_frac * st[S_LOCK_P] + PRESSURE_MARGIN_PA
    if st[S_ABS_ACTIVE + tg] < 0.5 and not (keep and held):
        st[S_LOCK_P] = -1.0
        st[S_LOCK_FALL] = 0.0
    elif (st[S_ABS_ACTIVE + tg] > 0.5 and p_prev >= 0.0 and p_now < p_prev - PRESSURE_MARGIN_PA and st[S_LOCK_FALL] < 0.5
          and p_prev <= st[S_P_REQ] + PRESSURE_MARGIN_PA):
        st[S_LOCK_P] = p_prev  # a dump starts: the lock level ABS found
        st[S_LOCK_FALL] = 1.0
    elif p_now >= p_prev:
        st[S_LOCK_FALL] = 0.0
    # (braking_lock_keep_flag, 0 = seeded defect = forgotten once ABS is quiet on the wheel) the level is kept while
    # ABS is quiet AND the wheel is held at or below the floor (held): there the floor is what keeps ABS quiet - a
    # quiet ABS is no evidence that the wheel carries more; a wheel quiet above the floor (re-built by the yaw gate's
    # branches) does carry more and the level goes (kept whatever the pressure: shipped check #273 of
    # test_blowout_blown_front_hold 0.567 -> 0.598 m vs none 0.594, tire_blowout_findings.md H8)
    st[S_LOCK_PREV] = p_now
    if st[S_LOCK_P] > 0.0:
        return min(p_bal, p.blowout_compensation_braking_lock_floor_frac * st[S_LOCK_P])
    return p_bal


@nb.njit(cache=True, nogil=True, error_model="numpy")
def rear_braking_rule(st, b, tg, mode, braking, p_mc, p_est, p):
    """A REAR blowout while the driver brakes: the compensating rear wheel's re-build after an ABS dump
    (``rear_braking_flag``, 0 = seeded defect = the code before). The driver's pressure reaches that wheel through the
    line as without the function (functions/esp.py passes a driver pressure above the held compensation pressure), ABS
    guarding it; the highest level it has reached so far (no more than the driver's pressure at the wheel, the master
    pressure through the proportioning valve) is kept in S_RB_HIGH. Once the wheel is below it by more than 1 bar (an
    ABS dump) its target S_P_BRAKE = max(the balance as planned and limited, S_P_REQ; that level, no more than the
    driver's pressure now), which the ESP applies as the front braking rule's target: re-built after the dump, and after
    a dump with slip evidence no higher than the pressure at the dump's start (S_P_PREDUMP, ABS's lock level) - what an
    ABS re-build does on a wheel without the function. Before, the re-build of a compensating wheel stopped at the plan
    (functions/esp.py, meant for a wheel the driver does not brake): with a plan of 0 (the blowout moment already pointed
    away from the blown side) each dump lowered the wheel for good and a braking driver's rear axle was emptied step by
    step (tire_blowout_findings.md G4: R2's targeted random 29 #38, RR 112 km/h mu 0.343 r650, lane follower, HBA, 0.28 rad/s
    wheel-speed noise: the compensating RL 47.6 -> 1.4 bar in 1.8 s at 0.2-2 % slip while the twin's rear pair carried
    22-27 bar; the car braked less and ran wide, 4.45 m vs 4.25 m without compensation; now 2.32 m).
    Tried and dropped (session g): the front braking rule's yaw feedback on the driver's share (down to the balance while
    the yaw points away from the blown side beyond the dead band): R2's #31 2.21 -> 1.42 m (none 0.57), but the lowering
    of the outer rear moved the single-source (TPMS path) detections into yaw-implausible rejections, random 23 #4
    0.64 -> 1.45 m (none 1.19), 21 points of 448 worse by > 0.05 m; the target at the driver's pressure without waiting
    for a dump (pumped up): 2 new violations (random 23 #4 1.33 m, targeted 5 #57)."""
    # (substitute_braking_flag, session n N3, tire_blowout_findings.md N3; 0 = the code before = the opposite rear
    # only) the same re-build on the SUBSTITUTE front: LIMITED with limit code 1 (the opposite rear's inlet diagnosed
    # stuck, _substitute brakes the front on the other side). That front takes the driver's pressure through the line
    # as the compensating rear does and ABS guards it; its re-build after a dump stopped at the plan as well (the plan
    # is lowered by the rear slip limit / capacity rule before the pedal: f_r41 #184, RL blown, RR stuck, 54 km/h,
    # mu 0.39: FR 31 bar at the pedal, each dump lower, held at 6.7 bar for 7 s against the twin's ABS-cycled 20-25
    # bar; the car braked at ~1.7 m/s^2 against ~3.5, still yawed toward RL and rolled off the road 26 s 'earlier'
    # than the twin, which stopped on it). A front: the driver's pressure is the master pressure (no proportioning)
    sub = (p.blowout_compensation_substitute_braking_flag > 0.5 and mode == LIMITED
           and st[S_LIMIT_CODE] == LIMIT_OTHER_AXLE and tg == _substitute(b) and tg < 2)
    if braking < 0.5 or not (sub or (tg == OPPOSITE[b] and (mode == BUILD or mode == HOLD))):
        st[S_P_PREDUMP] = -1.0
        st[S_RB_HIGH] = 0.0
        st[S_R3_RB_WHEEL] = -1.0
        return
    if p.blowout_compensation_substitute_braking_flag > 1.5 and st[S_R3_RB_WHEEL] != tg:
        # (value 2, review R3) the highest level and the dump's start belong to the wheel they were read on: when the
        # compensation moves from the opposite REAR (BUILD/HOLD) to the substitute FRONT (LIMITED, the opposite rear's
        # inlet diagnosed stuck after the detection) with the pedal held, value 1 carried the rear's S_RB_HIGH and the
        # rear's ABS lock level S_P_PREDUMP over to the front (no premise-false period in between to clear them)
        if st[S_R3_RB_WHEEL] >= 0.0:
            st[S_P_PREDUMP] = -1.0
            st[S_RB_HIGH] = 0.0
        st[S_R3_RB_WHEEL] = tg
    if sub:
        p_drv = max(p_mc, 0.0)
    else:
        p_drv = proportioned_pa(max(p_mc, 0.0), p.master_cylinder_proportioning_knee_pa,
                                p.master_cylinder_proportioning_slope_frac)
    st[S_RB_HIGH] = max(st[S_RB_HIGH], min(p_est[tg], p_drv))
    if p_est[tg] < st[S_RB_HIGH] - PRESSURE_MARGIN_PA:
        st[S_P_BRAKE] = max(st[S_P_REQ], min(p_drv, st[S_RB_HIGH]))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def rear_oversteer_cap(st, b, yaw_rate, p_est, p, r_ref=0.0, mode=-1):
    """Rear pair in an oversteer toward the blown side (``rear_oversteer_flag``, 0 = seeded defect = the rear pair
    capped only on a measured friction): while the sideslip phase-plane state is outside the stable region and the
    slide is the spin toward the blown side (``phase_plane_unstable`` with the direction test of ``spin_front_applies``:
    yaw toward the blown side, beta_dot + B1*beta away from it), the pair is held at its lower present pressure and
    lowered one step per period (the ESP's oversteer intervention under braking: the rear axle's brake pressure is
    reduced so the rear tires get their lateral force back - van Zanten, SAE 2000-01-1633). Back inside the region the
    cap ends (ABS and the other caps again).
    ``rear_oversteer_yaw_flag`` (0 = seeded defect = the phase plane alone): the ESP's yaw-rate oversteer criterion -
    after the build (not in BUILD: the released wheel's moment is still in the yaw), the measured yaw rate beyond the
    steered reference toward the blown side by more than the dead band, the car itself turning that way: the pair is
    HELD at its lower present pressure (not re-built by ABS/HBA; lowering stays the phase plane's), and S_OS_YAW_SEEN
    marks the detection confirmed (``blowout_step`` no longer rejects it as yaw-implausible: a released healthy wheel
    with the opposite front braked yaws the car away, never toward it). R1's random 3 b64 #58 (FL 93 km/h mu 0.60 r650,
    HBA): the rears were re-built 30 -> 56 bar while the car yawed 0.1-0.27 rad/s toward FL (reference 0.04): 1.270 ->
    0.889 m (none 0.357; what remains was built before the detection, tire_blowout_findings.md G6)."""
    yaw_os = (p.blowout_compensation_rear_oversteer_yaw_flag > 0.5
              and toward_blown_side(b, yaw_rate) > p.blowout_compensation_yaw_deadband_radps
              and toward_blown_side(b, yaw_rate + r_ref) > 0.0 and mode != BUILD)
    if p.blowout_compensation_rear_oversteer_yaw_sense_flag > 0.5:
        # (rear_oversteer_yaw_sense_flag) "the car itself turning toward the blown side" beyond the same dead band: in a
        # curve steered away from the blown side a braking car that hardly turns (|r| inside the dead band) is short of
        # the steered turn - an understeer of that turn, not a rotation toward the blown side; a car rotating toward
        # the blown side against a counter-steering driver (r beyond the dead band) still is the rule's oversteer
        yaw_os = yaw_os and toward_blown_side(b, yaw_rate + r_ref) > p.blowout_compensation_yaw_deadband_radps
    spin = phase_plane_spin(b, yaw_rate, st[S_BETA_EST], st[S_BETA_DOT], p)
    if spin or yaw_os:
        # the pair held at its lower present pressure (the cap never rises while it lasts); the phase-plane spin also
        # lowers it one step per period, the yaw-rate oversteer (rear_oversteer_yaw_flag) only holds it
        low = min(p_est[2], p_est[3])
        c = st[S_REAR_OS_CAP]
        c = low if c < 0.0 else min(c, low)
        if spin:
            c = max(c - p.blowout_compensation_rear_oversteer_step_pa, 0.0)
        else:
            st[S_OS_YAW_SEEN] = 1.0
        st[S_REAR_OS_CAP] = c
    else:
        st[S_REAR_OS_CAP] = -1.0
    if st[S_REAR_OS_CAP] >= 0.0:
        st[S_REAR_CAP] = st[S_REAR_OS_CAP] if st[S_REAR_CAP] < 0.0 else min(st[S_REAR_CAP], st[S_REAR_OS_CAP])


@nb.njit(cache=True, nogil=True, error_model="numpy")
def accel_friction_lower_bound(a_x, a_y, v_ref, fz_blown_n, p):
    """The road friction the car's MEASURED accelerations prove (``rear_accel_bound_flag``; rear_accel_circle_flag's
    mu). The accelerometers read the specific force, i.e. all contact and air forces over m; not all of it is tire
    friction of the kind F <= mu*F_z bounds:
    * air drag and rolling resistance R <= 0.5*rho*C_D*A*v^2 + f_max*m*g (common.md 3.1, 3.3; ECU nominal C_D*A at the
      reference speed, no head wind, f_max = ROLLING_RESISTANCE_MAX_FRAC): |tire F_x| >= m*|a_x| - R;
    * the blown front's rim drag D = mu_blow*F'_z with mu_blow <= mu (tire_blowout.md 4, eqs. 22-25; the plant's
      blowout.blown_drag_n: never above the road's peak mu*F'_z), ON TOP of that wheel's own tire force (which the
      friction circle bounds like any other): longitudinal only, so the tires carry at least
      (X - mu*F'_z, Y) with X = m*|a_x| - R, Y = m*|a_y|.
    The tires' resultant is at most mu*m*g (sum of F_i <= mu*F_z,i, spec 2.3), so mu >= the root of
    sqrt(max(X - mu*Z, 0)^2 + Y^2) = mu*G (Z = F'_z upper bound: the ECU's nominal load of that wheel at the measured
    a_x, without the flat's unloading, eqs. 3-4; G = m*g):
    (G^2 - Z^2)*mu^2 + 2*X*Z*mu - (X^2 + Y^2) = 0, or Y/G when the drag at mu = Y/G already explains X. Before this
    bound the rule took |a|/g, which contains both terms (tire_blowout_findings.md RI2 (session i): 14-15 % above the road's peak
    friction at the two curve points of tests/functions/test_blowout_rear_circle_cap.py, 0.12-0.13 g of rim drag and
    0.02-0.04 g of resistance). Not covered (no model of them in the plant; see the findings): accelerometer offset,
    body roll/pitch tilting the sensor (each adds g*sin(angle) to the reading), head wind."""
    m = p.body_mass_kg
    big_g = m * G_MPS2
    res = 0.5 * RHO_AIR_KGPM3 * p.body_drag_area_m2 * v_ref * v_ref + ROLLING_RESISTANCE_MAX_FRAC * big_g
    x = max(m * abs(a_x) - res, 0.0)
    y = m * abs(a_y)
    z = min(max(fz_blown_n, 0.0), 0.99 * big_g)
    mu_y = y / big_g
    if x <= mu_y * z:
        return mu_y
    a_q = big_g * big_g - z * z
    return (-x * z + math.sqrt(x * x * z * z + a_q * (x * x + y * y))) / a_q


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_circle_limit_mu(i, fz_straight_n, a_y, mu, blown, p):
    """Brake force [N] intact wheel ``i`` can carry inside its friction circle at friction ``mu`` next to its share of
    its axle's lateral force for a_y (``rear_circle_flag``): F_x <= sqrt((mu*F_z)^2 - F_y^2) (spec 2.3: the Dugoff
    resultant is bounded by mu*F_z), load and lateral share as in ``wheel_linear_limit_mu`` (spec eqs. 3-4, lateral
    force shared by cornering stiffness with the other wheel of the axle). 0 when the lateral force alone uses mu*F_z."""
    fz, fy = wheel_load_and_lateral_n(i, fz_straight_n, a_y, blown, p)
    cap = mu * max(fz, 0.0)
    return math.sqrt(cap * cap - fy * fy) if cap > fy else 0.0


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _cap_slip_pressure(st, tg, v_s, cap, dt, p):
    """Pressure at which the rear compensating wheel ``tg`` runs at the cap slip, from the window's measured point on
    its force-slip curve: the Dugoff curve with the ECU's C_x through the measured (F_x, s) (capacity inverted as in
    ``tire_capacity_estimate``) evaluated at the cap slip, as pressure with the nominal gain. In the linear region
    this is C_x*s_cap/(1 - s_cap); a linear scaling p*s_cap/s from a point deep in saturation (the lagging filtered
    slip lets a build overshoot) under-states it (F rises slower than s there): a light-braking rear point fell
    0.51 -> 1.51 m with it."""
    gain = p.brakes_rear_gain_nm_per_pa
    _, _, _, cap_f = tire_capacity_estimate(wheel_pressure_mean(st, tg), wheel_speed_mean(st, tg),
                                            wheel_accel_mps2(st, tg, dt) / p.body_wheel_radius_m, v_s, gain, p)
    x = cap / (1.0 - cap)
    lin = p.tires_longitudinal_stiffness_n * x
    if lin <= 0.0:
        return 0.0
    h = 0.5 * cap_f / lin
    f_cap = lin * (1.0 if h >= 1.0 else h * (2.0 - h))
    return f_cap * p.body_wheel_radius_m / gain


@nb.njit(cache=True, nogil=True, error_model="numpy")
def tire_capacity_rule(st, tg, vw, v_ref, a_y_ref, braking, p_est, requests, p, dt, a_x=0.0):
    """Compensating wheel (front or rear) limited by what its tire measurably gives (``tire_capacity_flag``, 0 = seeded
    defect; issue #10 round 3): the ECU plans from its nominal mu 0.8, which over-states a wet road. While the wheel
    carries added pressure, ``tire_capacity_check`` compares its measured brake force with the nominal linear force at
    its measured slip; q < CAP_FORCE_RATIO with s > CAP_MIN_SLIP for CAP_PERSIST_S = the tire has left its linear
    region; if the measured friction mu_est = capacity/F_z is also below the nominal, a low-friction limit is latched
    for the rest of this plan: the target is lowered to the H = 1 force mu_est*F_z/2 and to the plan re-scaled to
    mu_est (a rear wheel also to ``rear_linear_limit_mu`` at mu_est, with its lateral share), never below the driver's
    pressure, and not while the driver brakes; above
    the lowered target the added pressure is dumped, otherwise held (no further build)."""
    gain = p.brakes_front_gain_nm_per_pa if tg < 2 else p.brakes_rear_gain_nm_per_pa
    # front wheel: the evidence judged at the upper end of the pad-friction tolerance (below); rear wheel: at the nominal
    # gain - a rear wheel whose saturation is missed spins the car (the 78/81 km/h low-friction rear points with 23-30 %
    # weaker pads were 0.76/0.93 m vs none 0.68/0.80 with the tolerance), while its target is already held in the linear
    # region by the rear slip limit, where q = k_cx/k_gain stays above 0.8 for gain/C_x errors up to 25 %
    gain_hi = 1.0 + (p.blowout_compensation_brake_gain_tolerance_frac if tg < 2 else 0.0)  # 0 = seeded defect
    if p.blowout_compensation_signal_filter_flag > 0.5:
        # filtered (signal_filter_flag): speed, pressure and the least-squares wheel deceleration over the same window
        # (the one-period difference made J*omega_dot/R noise of +-80 N per 0.1 rad/s of wheel-speed noise)
        v_s = slip_reference_mps(st, int(st[S_BLOWN]), tg, v_ref, braking)
        p_m, v_m, wdot = wheel_pressure_mean(st, tg), wheel_speed_mean(st, tg), wheel_accel_mps2(st, tg, dt) / p.body_wheel_radius_m
        fx, s_tg, q, cap = tire_capacity_estimate(p_m, v_m, wdot, v_s, gain, p)
        q_hi, cap_hi = q, cap
        if gain_hi != 1.0:  # a rear wheel (and tolerance 0) is judged at the nominal gain: the same evidence
            _, _, q_hi, cap_hi = tire_capacity_estimate(p_m, v_m, wdot, v_s, gain * gain_hi, p)
    else:
        prev = st[S_VW_PREV] if st[S_VW_PREV] >= 0.0 else vw[tg]
        fx, s_tg, q, cap = tire_capacity_check(p_est[tg], vw[tg], prev, v_ref, dt, gain, p)
        q_hi, cap_hi = q, cap
        if gain_hi != 1.0:
            _, _, q_hi, cap_hi = tire_capacity_check(p_est[tg], vw[tg], prev, v_ref, dt, gain * gain_hi, p)
    st[S_VW_PREV] = vw[tg]
    filt = p.blowout_compensation_signal_filter_flag > 0.5
    mu_est = cap / max(st[S_FZ_TARGET], 1.0)  # the friction the tire measurably has (capacity over the ECU's load)
    # the evidence is judged at the upper end of the pad-friction tolerance (brake_gain_tolerance_frac): the most brake
    # force, hence the least saturation and the most friction, that the measurement allows; with more pad friction
    # than nominal the nominal gain under-states F_x (q = f(H)/k_gain) and a linear tire on a dry road read saturated
    mu_hi = cap_hi / max(st[S_FZ_TARGET], 1.0)
    # filtered (signal_filter_flag): the whole evidence must persist - saturation AND a friction below the nominal over
    # CAP_PERSIST_S, not a saturation phase on a good road followed by one transient sample of low mu_est (closed loop
    # LF 60 after an ABS dump/re-build: mu_est 0.88 -> 0.79 for one sample latched the target 44.5 -> 31.4 bar, E)
    low_mu = mu_hi < p.blowout_compensation_mu_estimate_frac or not filt
    if braking < 0.5 and p_est[tg] > st[S_P_START] + PRESSURE_MARGIN_PA and s_tg > CAP_MIN_SLIP and q_hi < CAP_FORCE_RATIO and low_mu:
        st[S_LOW_S] += dt
    else:
        st[S_LOW_S] = min(st[S_LOW_S], 0.0) if filt else 0.0
    if st[S_LOW_S] >= CAP_PERSIST_S - 1e-9 and mu_hi < p.blowout_compensation_mu_estimate_frac:
        # out of the linear region on a road with less friction than the ECU planned with: the wheel is kept at the
        # Dugoff H = 1 force of its measured capacity (F = mu*F_z/2, spec 2.3), and at most at the pressure re-planned
        # with the measured friction (without the driver's brake, the rule's case, the intact wheels carry no brake
        # force and M_z_blow = -+b*mu*k_blow*F'_z, eqs. 22-25, and p_w, eq. 28, are proportional to mu); re-evaluated
        # while the wheel stays out, the lowest kept (latched)
        f_hold = 0.5 * cap
        if tg >= 2:
            fx_lin, _ = rear_linear_limit_mu(tg, st[S_FZ_TARGET], a_y_ref, mu_est, p)
            f_hold = min(f_hold, fx_lin)
        p_replan = st[S_P_ADD] * mu_est / p.blowout_compensation_mu_estimate_frac
        f_hold = min(f_hold, (st[S_P_START] + p_replan) * gain / p.body_wheel_radius_m)
        # (understeer_cap_freeze_flag, 0 = seeded defect) not while the understeer rule holds the target below the plan
        # (S_US_LIMITED): the wheel is then deliberately braked less than the plan asks, at a slip its lowered pressure
        # sets, and the pure-longitudinal inversion of a tire carrying the curve reads mu*C_x*s/sqrt((C_x*s)^2 +
        # (C_a*tan(alpha))^2) (front_circle_measured_flag note) - falling with the pressure the rule dumped, the
        # friction direction of the held wheel, not its capacity; the restore returns to the plan capped by the last
        # measurement made at the plan's own pressure (R1: S_F_CAP lowered while held, then undone by the restore); the
        # braking rule's S_MU_MEAS is left as before (its front cap reads the same inversion as the longitudinal capacity)
        valid = p.blowout_compensation_understeer_cap_freeze_flag < 0.5 or st[S_US_LIMITED] < 0.5
        if st[S_CAP_LATCHED] < 0.5 or (valid and f_hold < st[S_F_CAP]):
            st[S_F_CAP] = f_hold
        if st[S_MU_MEAS] <= 0.0 or mu_est < st[S_MU_MEAS]:
            st[S_MU_MEAS] = mu_est  # the lowest measured friction, for the braking rule (braking_rule; its front cap
            #   uses this reading as the longitudinal capacity next to the lateral force, front_circle_measured_flag)
        st[S_CAP_LATCHED] = 1.0
        st[S_P_REQ] = max(min(st[S_P_REQ], st[S_F_CAP] * p.body_wheel_radius_m / gain), st[S_P_START])

    if st[S_CAP_LATCHED] > 0.5:
        if p_est[tg] > st[S_P_REQ] + PRESSURE_MARGIN_PA and braking < 0.5:
            requests[tg] = Q_RELEASE
        elif requests[tg] != Q_RELEASE:
            requests[tg] = Q_HOLD
    if p.blowout_compensation_measured_mu_raise_flag > 0.5:
        measured_mu_raise(st, tg, v_ref, braking, p_est, gain, p, dt, a_x, a_y_ref)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def measured_mu_raise(st, tg, v_ref, braking, p_est, gain, p, dt, a_x=0.0, a_y=0.0):
    """The braking rule's measured friction S_MU_MEAS raised by a linear reading (``measured_mu_raise_flag``, 0 =
    seeded defect = only ever lowered; tire_blowout_findings.md RG/G7, random 17 #36). S_MU_MEAS is the lowest capacity read while
    the compensating front was out of its linear region before the pedal - a build overshoot and the ABS dump after it,
    where the filtered pressure and slip lag the wheel (random 17 #36: 0.284 at the overshoot, then 0.246/0.202/0.176 on
    the recovering wheel; the road's peak 0.453): the wheel's present force on a lagging slip, not its limit. The
    braking rule then held the front at mu_meas*F_z (13.3 bar) and the rear pair in its linear region at mu_meas
    (7 bar) under a 166-bar panic pedal, no wheel near ABS. A tire in the Dugoff linear region (f(H) = 1, spec 2.3) has
    H = mu*F_z*(1 - s)/(2*C_x*s) >= 1: a force carried linearly proves mu*F_z >= 2*C_x*s/(1 - s) (the capacity
    inversion at q = 1). While the driver brakes and the compensating front (no ABS activity, pressure settled: the
    window's mean within 1 bar of the estimate) shows q >= CAP_FORCE_RATIO at s > CAP_MIN_SLIP for CAP_PERSIST_S, the
    measured friction is raised to that reading's capacity inversion (``tire_capacity_estimate``: 2*C_x*s/(1 - s) at
    q = 1, 2*(1 - sqrt(1 - q))*C_x*s/(1 - s) below it) over F_z, F_x judged at the LOWER end of the pad-friction
    tolerance (the least force the measurement allows), at most to the ECU's nominal mu_estimate_frac (the friction it
    uses without a measurement). The braking rule's caps then rise with the force the wheel measurably carries
    linearly and stop where it leaves the linear region (Dugoff: linear up to F = mu*F_z/2, so the bound never
    exceeds the road's friction); never lowered here (the lowering stays the capacity rule's, without the pedal).

    ``measured_mu_bound_flag`` (0 = seeded defect = the rule above; tire_blowout_findings.md H1, docs item 10 (a)-(d)): that
    reading over-stated the friction wherever the plant differs from the ECU's data - the brake force taken at the cold
    band's lower edge (0.82) while fade reaches 0.66, q compared with the nominal C_x while C_x is known to
    +-longitudinal_stiffness_tolerance_frac, and the capacity over the plan-time load while the wheel is measured under
    braking load transfer (a forward Dugoff scan: up to 1.6 x the true mu). Now a guaranteed lower bound (``mu_lower_
    bound``): Dugoff (spec 2.3, combined slip too) gives F_x = C_x*s/(1 - s)*f(H) and mu*F_z = 2*H*sqrt((C_x*s)^2 +
    (C_a*tan(alpha))^2)/(1 - s) >= F_x*2*H/f(H) = F_x*2/(2 - H) (H < 1; 2*F_x at H >= 1), increasing in H; with the
    brake gain at least the fade edge (brake_gain_fade_low_frac) F_x >= F_lo, and with C_x at most (1 + tol)*C_x,nom
    f(H) >= q_lo/(1 + tol), hence H >= H_lo = 1 - sqrt(1 - f_lo) and mu*F_z >= 2*F_lo/(1 + sqrt(1 - f_lo)) - no C_x
    lower bound and no alpha needed, valid for any q (the q >= CAP_FORCE_RATIO gate is dropped: a saturated reading
    still proves mu*F_z >= F_lo, the friction circle). Over the wheel's present load at most: the ECU's load at the
    measured a_x with the blowout transfer (the braking rule's own ``ecu_loads``) plus the lateral transfer at a_y.
    ``measured_mu_lower_flag`` (0 = seeded defect = a raise is kept to the end of the stop; item 10 (e)): an ABS dump
    on the compensating front under the pedal (S_P_PREDUMP, slip evidence) marks its present limit; the raise is taken
    back to the force at the dump's start (upper pad gain: the most force the pressure allows, over the least load)
    and never below the value before the raise (S_MU_PRE) - a raise proven on a better patch does not outlive the
    wheel's own limit."""
    if braking < 0.5 or tg >= 2 or st[S_MU_MEAS] <= 0.0 or st[S_FZ_TARGET] <= 1.0:
        st[S_LIN_S] = 0.0
        st[S_MU_PRE] = -1.0
        return
    bound = p.blowout_compensation_measured_mu_bound_flag > 0.5
    v_s = slip_reference_mps(st, int(st[S_BLOWN]), tg, v_ref, braking)
    p_m, v_m = wheel_pressure_mean(st, tg), wheel_speed_mean(st, tg)
    wdot = wheel_accel_mps2(st, tg, dt) / p.body_wheel_radius_m
    settled = abs(p_m - p_est[tg]) < PRESSURE_MARGIN_PA
    if bound:
        # the window's mean speed and pressure are WS_WINDOW_N/2 periods old: the slip is taken against the reference
        # of that time (the decelerating car was faster then; v_ref now under-read the slip by |a_x|*17.5 ms/v -
        # random 17 #36: 1.45 % read vs 1.91 % true at 13 bar, which made a linear-looking q)
        v_s = v_s - a_x * 0.5 * (WS_WINDOW_N - 1) * dt
        fz_hi, fz_lo = mu_raise_loads_n(st, tg, a_x, a_y, p)
        if (p.blowout_compensation_measured_mu_lower_flag > 0.5 and st[S_MU_PRE] > 0.0
                and st[S_ABS_ACTIVE + tg] > 0.5 and st[S_P_PREDUMP] > 0.0):
            # (measured_mu_lower_flag) ABS found the wheel's limit: the raise no higher than the force there
            g_hi = 1.0 + p.blowout_compensation_brake_gain_tolerance_frac
            mu_abs = g_hi * gain * st[S_P_PREDUMP] / p.body_wheel_radius_m / max(fz_lo, 1.0)
            st[S_MU_MEAS] = min(st[S_MU_MEAS], max(st[S_MU_PRE], mu_abs))
        if (p.blowout_compensation_front_abs_limit_flag > 0.5 and st[S_ABS_ACTIVE + tg] > 0.5
                and st[S_P_PREDUMP] > 0.0):
            # (front_abs_limit_flag) ABS found the wheel's limit: the force at the dump's start at the fade edge of
            # the pad gain, with the wheel's deceleration, is a lower bound of mu*F_z (friction circle, spec 2.3)
            if (p.blowout_compensation_abs_dump_bound_flag > 0.5
                    and p.blowout_compensation_abs_dump_noise_flag > 0.5):
                # (abs_dump_noise_flag, 0 = seeded defect = the reading below) the same friction circle over the
                # window before the dump (``dump_window_reading``: weighted mean force = a lower bound of mu*F_z),
                # its deceleration taken DUMP_NOISE_SIGMAS of the design noise high: the 3-sample a_w below has
                # sigma 15 m/s^2 at 0.3 rad/s (140 N, 7 % of the force per sigma; tire_blowout_findings.md RH3: above the plant's
                # F_x in 40 % of noisy draws)
                a_hi = st[S_AW_DUMPWIN] + DUMP_NOISE_SIGMAS * dump_window_decel_sigma_mps2(p, dt)
                t_lo = p.blowout_compensation_brake_gain_fade_low_frac * gain * st[S_P_DUMPWIN]
                t_lo -= p.body_wheel_inertia_kgm2 * max(a_hi, 0.0) / p.body_wheel_radius_m
                mu_dump = max(t_lo, 0.0) / p.body_wheel_radius_m / max(fz_hi, 1.0)
            elif p.blowout_compensation_abs_dump_bound_flag > 0.5:
                # (abs_dump_bound_flag, 0 = seeded defect = the line below) the friction circle alone, F_x <= mu*F_z,
                # with the force AT the dump's start: the brake torque at the fade gain less the wheel's own spin-down
                # J*a_w/R then (J*omega_dot = F_x*R - T_b). The Dugoff factor 2/(1 + sqrt(1 - f)) needs the slip of
                # the same instant - the present window's slip (a wheel recovering after the dump) with the pressure
                # before it made a locking wheel look linear (up to 2 x F); and the present wdot is not the lock's
                t_lo = p.blowout_compensation_brake_gain_fade_low_frac * gain * st[S_P_PREDUMP]
                t_lo -= p.body_wheel_inertia_kgm2 * max(st[S_AW_PREDUMP], 0.0) / p.body_wheel_radius_m
                mu_dump = max(t_lo, 0.0) / p.body_wheel_radius_m / max(fz_hi, 1.0)
            else:
                mu_dump = mu_lower_bound(st[S_P_PREDUMP], v_m, min(wdot, 0.0), v_s, gain, p) / max(fz_hi, 1.0)
            mu_dump = min(mu_dump, p.blowout_compensation_mu_estimate_frac)
            if mu_dump > st[S_MU_MEAS]:
                if st[S_MU_PRE] <= 0.0:
                    st[S_MU_PRE] = st[S_MU_MEAS]
                st[S_MU_MEAS] = mu_dump
        mu_lin = mu_lower_bound(p_m, v_m, wdot, v_s, gain, p) / max(fz_hi, 1.0)
        evidence = v_s > 0.0 and (v_s - v_m) / max(v_s, 1.0) > CAP_MIN_SLIP
    else:
        g_lo = 1.0 - p.blowout_compensation_brake_gain_tolerance_frac
        _, s_tg, q, cap = tire_capacity_estimate(p_m, v_m, wdot, v_s, gain * g_lo, p)
        mu_lin = cap / st[S_FZ_TARGET]
        evidence = s_tg > CAP_MIN_SLIP and q >= CAP_FORCE_RATIO
    if evidence and settled and st[S_ABS_ACTIVE + tg] < 0.5:
        st[S_LIN_S] += dt
    else:
        st[S_LIN_S] = 0.0
    if st[S_LIN_S] >= CAP_PERSIST_S - 1e-9:
        mu_lin = min(mu_lin, p.blowout_compensation_mu_estimate_frac)
        if mu_lin > st[S_MU_MEAS]:
            if st[S_MU_PRE] <= 0.0:
                st[S_MU_PRE] = st[S_MU_MEAS]
            st[S_MU_MEAS] = mu_lin


@nb.njit(cache=True, nogil=True, error_model="numpy")
def mu_lower_bound(p_wheel_pa, vw_now, omega_dot, v_ref, gain_nm_per_pa, p):
    """Friction capacity mu*F_z [N] the braked wheel's reading guarantees whatever the pad friction and C_x within
    their tolerances (``measured_mu_bound_flag``; derivation in ``measured_mu_raise``): F_lo = the brake force at the
    fade edge of the pad gain (brake_gain_fade_low_frac x nominal), q_lo = F_lo/(C_x,nom*s/(1 - s)), f_lo =
    min(q_lo/(1 + longitudinal_stiffness_tolerance_frac), 1), mu*F_z >= 2*F_lo/(1 + sqrt(1 - f_lo))."""
    fx, _, q, _ = tire_capacity_estimate(p_wheel_pa, vw_now, omega_dot, v_ref,
                                         gain_nm_per_pa * p.blowout_compensation_brake_gain_fade_low_frac, p)
    if fx <= 0.0:
        return 0.0
    f_lo = min(q / (1.0 + p.blowout_compensation_longitudinal_stiffness_tolerance_frac), 1.0)
    return 2.0 * fx / (1.0 + math.sqrt(1.0 - f_lo))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def mu_raise_loads_n(st, tg, a_x, a_y, p):
    """(upper, lower) bound [N] of the compensating wheel ``tg``'s present load as the ECU knows it: the braking
    rule's load (``ecu_loads`` at the measured a_x, the blowout transfer of eqs. 3-4) plus / minus the lateral load
    transfer at a_y (``wheel_load_and_lateral_n``; its sign is not needed for a bound)."""
    b = int(st[S_BLOWN])
    f0, f1, f2, f3 = blown_ecu_loads(b, a_x, p) if b >= 0 else ecu_loads(p, a_x)
    gl = (f0, f1, f2, f3)
    fz_a, _ = wheel_load_and_lateral_n(tg, gl[tg], a_y, b, p)
    d = abs(fz_a - gl[tg])
    return gl[tg] + d, max(gl[tg] - d, 1.0)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def front_spin_keep(b, tg, yaw_dev, p, yaw_meas, code, beta_est):
    """True = no refusal of a RUNNING compensation beyond the stable region (``front_spin_keep_flag``, 0 = seeded
    defect = refused whatever the rotation; tire_blowout_findings.md G5, braking 47 #69; called from the BUILD/HOLD/LIMITED ->
    REFUSED transition only): a FRONT blowout compensated on the other front wheel while the car's yaw rate exceeds the
    steering reference TOWARD the blown side (``yaw_dev`` = measured - ``reference_yaw_rate``: oversteer toward the
    flat). The compensation's moment then is the ESP's own answer to that rotation: the compensating front is the OUTER
    front of the rotation, and an ESP answers oversteer by braking the outer front wheel (van Zanten, Bosch ESP
    Systems: 5 Years of Experience, SAE 2000-01-1633; Bosch Automotive Handbook, ESP), the inner (blown) front unbraked
    - the module's rear-blowout counterpart is the spin-front rule (spin_front_flag). Standing down there takes the
    counter-moment off while it is still being built (valve time, eq. 30) against the drag that is turning the car
    (#69: refused 80 ms after the detection, 13.58 m vs none 11.29 m, both spun; kept 1.53 m, no spin). Not at the
    detection (IDLE/REJECTED -> REFUSED): a car already beyond the bounds when the blowout is found is in a spin the
    feed-forward plan was not made for; keeping it there slowed the spin without stopping it and lengthened the slide
    (braking 5 #1 6.81 -> 14.08 m, none 6.94; random 41 #407 4.00 -> 5.60, none 4.03). Rotating AWAY from the blown side
    the compensation's moment would add to the rotation: refused as before."""
    if p.blowout_compensation_front_spin_keep_flag < 0.5:
        return False
    if b < 0 or b >= 2 or tg != OPPOSITE[b]:
        return False
    if p.blowout_compensation_front_spin_keep_rotation_flag > 0.5:
        # (front_spin_keep_rotation_flag) the spin toward the blown side as the spin-front rule defines it
        # (spin_front_applies): the measured rotation itself toward the blown side - beyond the yaw bound a reference
        # further out than the rotation (a yaw deviation toward the blown side while the car rotates AWAY from it) is
        # a target the road cannot carry (Rajamani ch. 8 bounds the desired yaw rate by 0.85*mu*g/u), and the
        # compensating front's moment would add to that rotation; and a sideslip-bound trigger only as the slide of
        # that spin (beta pointing away from the blown side; toward it: the slide of the opposite rotation)
        if toward_blown_side(b, yaw_meas) <= 0.0:
            return False
        if code == LIMIT_SIDESLIP_BOUND and toward_blown_side(b, beta_est) >= 0.0:
            return False
    return toward_blown_side(b, yaw_dev) > 0.0
