"""I2's targeted FL search in low-friction curves with a braking driver (session 2026-11-24 i, task I10;
tire_blowout_findings.md "I2 (session i)" and "I10 (session i)", tire_blowout_sessions.md status h, "Session i, I10").

I2 ran ``falsify tire_blowout -r tire_blowout.no_worse_than_no_compensation --optimizer random --seed 61|83 -n 96
-R wheel=fl -R curve=r650,r1000 -R braking=brakes -R mu=0.3..0.5`` at main cc64ff5 + I2's rule and found five
violations. Re-run at main 568d131 (I1-I7 merged; the only change on these points is I4's named_front_gma_flag) two
are fixed, three stay and one appears (83 #27); by mechanism:

* A - 83 #90 (FL 106 km/h, mu 0.30, 650 m curve, fixed steering, slow pedal to 0.45) and 83 #9 (FL 75 km/h, mu 0.37):
  the TPMS-named window. The named flat FL's ABS started the ESP's yaw-moment build-up delay (GMA) on the intact FR,
  held at 23-27 bar (wheel mode H) against the driver's 160 bar for 2.8 s; the car braked less and ran wide (5.921 m
  vs the twin's 2.165 m; #9 1.327 vs 0.290). I4's ``esp.named_front_gma_flag`` (landed after I2's search) fixes both:
  0.884 / 0.263 m. Rows below: no worse than the twin at main; with the flag at 0 (the code before) worse.
* B - 61 #8 (FL 116 km/h, mu 0.46, 650 m curve, panic pedal 147 bar with HBA): both cars spin toward the blown side
  (yaw 60-75 deg/s; the steered 2.9 deg/s). The compensated car's yaw runs ahead of the twin's from the named window
  on (12.3 vs 9.2 deg/s at the detection, 1.42 s: its ESP reference leaves the named FL out, FR's ABS keeps FR at 8 %
  slip instead of the twin's 14 % - more lateral force on the outer front) and the released flat FL (2 bar vs the
  twin's 19) brakes it less into the spin: 7.955 vs 5.354 m. Its outer rear RR sits in one ABS hold at 10-14 % slip
  from 1.175 s to 1.86 s, across the detection, where the twin's RR reaches 20 % and is dumped at 1.34 s. I4's rule made it worse (6.264 at flag 0, refused
  at 1.655 s instead of 2.29 s). With I5's ABS hold time limit (``esp.abs_hold_limit_flag``, shipped 0) on BOTH cars:
  5.080 vs 4.788 m. Strict xfail.
* C - 61 #22 (FL 106 km/h, mu 0.49, 650 m curve toward FL, pedal after the detection): G2's blown-inner-front hold
  (``blown_front_hold_flag``) cycles the flat FL between released (~1 bar) and re-applied (15-37 bar) ten times as the
  yaw crosses the steered reference (tire_blowout_findings.md I3); the car drifts out 2.156 vs 1.727 m. With the hold off the
  paper's release gives 0.555 m (I3's relay, a candidate deleted in session j: 1.979). Strict xfail + attribution.
* D (status h item 8, the ABS hold without a time limit; B shares it) - 61 #45 (FL 51 km/h, mu 0.32, 1000 m
  curve: steered yaw 0.8 deg/s, inside the 1 deg/s dead band, so treated as a
  straight road): the paper's release of the braked flat FL while the intact FR sits in one uninterrupted ABS hold at
  15-16 % slip for 3.0 s (status h item 8) - the release's moment, set by the pedal, yaws the car away from the blown
  side 1.3 deg/s below the reference: the mirror image of the twin (-0.494 vs +0.469 m at the end; 0.493 vs 0.470 m).
  With the ABS hold time limit on both cars no violation (0.432 vs 0.483 m). Strict xfail. 83 #27 (FL 115 km/h, mu
  0.33, 1000 m curve, lane follower, panic pedal; +0.0003 m in I2's search, a violation at main: 0.461 vs 0.402 m,
  I4's rule 0.401 -> 0.461): the same, FR in one ABS hold at 16-17 % slip for the last 2.5 s (twin 1.5 s). Strict xfail.

References, independent of the function's code: requirement tire_blowout.no_worse_than_no_compensation (the twin is
the same point without the function, paper 004 Fig. 4 curve 2); the ESP valve modes (plant/brakes/esp_unit.py) and
ABS modes (functions/abs.py) as plant/ECU channels; the twin's own trace.
"""
from __future__ import annotations

import numpy as np
import pytest

from tests.support import envelope_point_run
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
BAR = 1.0e5
NAMED_GMA_DEFECT = ("vehicle.esp.named_front_gma_flag=0",)  # the code before I4's rule
HOLD_OFF = ("vehicle.blowout_compensation.blown_front_hold_flag=0",)  # the paper's release of the blown front
ABS_HOLD_LIMIT = ("vehicle.esp.abs_hold_limit_flag=1",)  # I5's candidate (platform ESP, shipped 0): both cars
ABS_HOLD = 1  # functions/abs.py modes OFF HOLD DUMP BUILD
W_H, W_HI = 3, 2  # ESP wheel valve modes (plant/brakes/esp_unit.py: N B HI H D BP BPM T)
TPMS_ALARM_DROP_FRAC = 0.25  # FMVSS 138 low-pressure warning (suv_bj2500.toml blowout.tpms_alarm_drop_frac source)
# /tmp/i2/ts/s83_on/falsify.json and s61_on/falsify.json (I2's targeted search, random 83 / 61, -n 96)
P83_90 = {"speed": 106.05106094257113, "mu": 0.3016622041638323, "delay": 0.47201692096391534,
          "wheel_speed_noise": 0.08681195896789176, "noise_seed": 7067.0, "brake_gain": 1.0142454110315064,
          "brake.start_s": 1.1552565602262608, "brake.level_frac": 0.4531154285760136,
          "brake.rate_per_s": 0.4402634221973763, "braking": "brakes", "wheel": "fl", "driver": "fixed",
          "curve": "r650"}
P83_9 = {"speed": 75.06115183923461, "mu": 0.36641101757099054, "delay": 0.2567241249196448,
         "wheel_speed_noise": 0.11656907156353044, "noise_seed": 3472.0, "brake_gain": 1.0323479977872538,
         "brake.start_s": 1.0532411468773921, "brake.level_frac": 0.15989992850754403,
         "brake.rate_per_s": 0.6656553169543822, "braking": "brakes", "wheel": "fl", "driver": "fixed",
         "curve": "r650"}
P61_8 = {"speed": 116.1803067230472, "mu": 0.4643750560693202, "delay": 0.3858330290929928,
         "wheel_speed_noise": 0.05276645989166434, "noise_seed": 9517.0, "brake_gain": 1.101482085673667,
         "brake.start_s": 0.8179332858357435, "brake.level_frac": 0.25852768368993173,
         "brake.rate_per_s": 18.219265290710123, "braking": "brakes", "wheel": "fl", "driver": "fixed",
         "curve": "r650"}
P61_22 = {"speed": 105.64040531450647, "mu": 0.485245090154528, "delay": 0.27866973963406677,
          "wheel_speed_noise": 0.29837619035252333, "noise_seed": 8716.0, "brake_gain": 1.1192417562560197,
          "brake.start_s": 1.4018381522506136, "brake.level_frac": 0.18837601528314624,
          "brake.rate_per_s": 13.988655380368476, "braking": "brakes", "wheel": "fl", "driver": "fixed",
          "curve": "r650"}
P61_45 = {"speed": 51.40484716669853, "mu": 0.3171956411383364, "delay": 0.024611448532422368,
          "wheel_speed_noise": 0.14250619136026793, "noise_seed": 7836.0, "brake_gain": 0.9134280445764112,
          "brake.start_s": 0.8065001148998936, "brake.level_frac": 0.1343534267762,
          "brake.rate_per_s": 29.790672037020176, "braking": "brakes", "wheel": "fl", "driver": "fixed",
          "curve": "r1000"}
# 83 #27: +0.0003 m in I2's search (cc64ff5 + I2), a violation at main 568d131 (I4's rule: 0.401 -> 0.461 m, none 0.402)
P83_27 = {"speed": 114.80016030528054, "mu": 0.33389217412218863, "delay": 0.32058882170162933,
          "wheel_speed_noise": 0.0044501572580147196, "noise_seed": 9651.0, "brake_gain": 0.8285535558914343,
          "brake.start_s": 0.794695266336418, "brake.level_frac": 0.3742311335982508,
          "brake.rate_per_s": 16.590630763734506, "braking": "brakes", "wheel": "fl", "driver": "follow",
          "curve": "r1000"}
NAMED = {"s83_90": P83_90, "s83_9": P83_9}
LEFT = {"s61_8": P61_8, "s61_22": P61_22, "s61_45": P61_45, "s83_27": P83_27}
POINTS = {**NAMED, **LEFT}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


@pytest.fixture(scope="module")
def run(env):
    cache = {}

    def get(name, baseline=False, sets=()):
        key = (name, baseline, tuple(sets))
        if key not in cache:
            cache[key] = envelope_point_run(env, POINTS[name], baseline=baseline, sets=sets)
        return cache[key]

    return get


def _dev(r):
    return r.metrics[METRIC]


def _longest_run_s(mask, t):
    """Longest uninterrupted stretch of ``mask`` in seconds (sample period from ``t``)."""
    best = cur = 0
    for m in mask:
        cur = cur + 1 if m else 0
        best = max(best, cur)
    return best * float(t[1] - t[0])


@pytest.mark.parametrize("name", sorted(NAMED))
def test_named_window_points_no_worse_than_none(run, name):
    """A: at main the two named-window points are no worse than the twin (83 #90 0.884 vs 2.165 m, #9 0.263 vs
    0.290 m; I2's search at cc64ff5: 5.921 / 1.327 m)."""
    on, none = _dev(run(name)), _dev(run(name, baseline=True))
    assert on <= none, f"{on:.3f} m vs none {none:.3f} m"


@pytest.mark.parametrize("name", sorted(NAMED))
def test_named_window_points_worse_with_defect(run, name):
    """Negative control of the row above: with ``named_front_gma_flag = 0`` (the code before I4's rule) both points
    are worse than the twin (5.921 / 1.327 m). Session n (N1, class C corrected): judged to standstill #83_90's cars
    both leave the road (run max 16.906 vs the twin's 24.164 m, beyond the road edge: not ranked), so the same check is
    both rows of the requirement (never_worse_rows): the defect leaves the road 2.715 s BEFORE the twin (s83_9: road
    deviation 0.949 vs 0.367 m)."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(run(name, sets=NAMED_GMA_DEFECT), run(name, baseline=True))
    assert min(rows.values()) < 0.0, (name, rows)


@pytest.mark.parametrize("sets,gma", [((), False), (NAMED_GMA_DEFECT, True)])
def test_named_window_gma_on_intact_front(run, sets, gma):
    """A, mechanism at 83 #90: in the named window (TPMS alarm, no detection yet, compensation idle, driver braking)
    the intact FR is held by the ESP (valve mode H/HI) while its own ABS is off - the GMA's pattern - for most of the
    window with the defect, never at main."""
    tr = run("s83_90", sets=sets).trace
    win = ((np.asarray(tr["blowout_frac"]) >= TPMS_ALARM_DROP_FRAC)
           & (np.asarray(tr["blowout_detected_wheel_index"]) < 0)
           & (np.asarray(tr["blowout_mode_index"]) == 0)
           & (np.asarray(tr["master_pressure_pa"]) > 2.0e5))
    held = (np.isin(np.asarray(tr["wheel_mode_fr_index"]), (W_H, W_HI))
            & (np.asarray(tr["abs_mode_fr_index"]) == 0))
    n_win, n_held = int(win.sum()), int((held & win).sum())
    assert n_win >= 20, "the point must have a named window under the pedal"
    assert (n_held > n_win // 4) == gma, (n_win, n_held)


@pytest.mark.xfail(strict=True, reason="B/C/D (tire_blowout_findings.md I10): 61 #8 7.955 vs 5.354 m (both spin), #22 2.156 vs "
                                       "1.727 m (blown inner front hold/release cycling), #45 0.493 vs 0.470 m "
                                       "(release with FR in a 3-s ABS hold), 83 #27 0.461 vs 0.402 m (FR in a "
                                       "2.5-s ABS hold)")
@pytest.mark.parametrize("name", sorted(LEFT))
def test_left_points_no_worse_than_none(run, name):
    """B, C, D: the four violations of the two searches at main 568d131."""
    on, none = _dev(run(name)), _dev(run(name, baseline=True))
    assert on <= none, f"{on:.3f} m vs none {none:.3f} m"


def test_22_blown_inner_front_cycles(run):
    """C, mechanism: after the pedal the flat inner FL is re-applied from a release (< 3 bar) to above 15 bar at
    least 4 times (measured 10; the twin's FL, never released by a function, once: its ABS)."""
    def cycles(r):
        t = np.asarray(r.trace["time_s"])
        p = np.asarray(r.trace["wheel_pressure_fl_pa"])[t > P61_22["brake.start_s"]] / BAR
        low, n = False, 0
        for x in p:
            if not low and x < 3.0:
                low = True
            elif low and x > 15.0:
                n, low = n + 1, False
        return n
    n_on, n_none = cycles(run("s61_22")), cycles(run("s61_22", baseline=True))
    assert n_on >= 4 and n_none <= 1, (n_on, n_none)


def test_22_attributed_to_blown_front_hold(run):
    """C, attribution: with the hold off (the paper's release of the blown front) #22 is no worse than the twin
    (0.555 vs 1.727 m) - the cycling hold is what loses it."""
    off, none = _dev(run("s61_22", sets=HOLD_OFF)), _dev(run("s61_22", baseline=True))
    assert off <= none, f"{off:.3f} m vs none {none:.3f} m"


@pytest.mark.parametrize("name", ["s61_45", "s83_27"])
def test_compensating_front_abs_hold_longer_than_twin(run, name):
    """D, mechanism: the compensating FR sits in ONE uninterrupted ABS hold (between the 10 % hold and 20 % dump
    thresholds) longer than 2 s and longer than any of the twin's FR holds (61 #45 3.0 vs 1.4 s, 83 #27 2.5 vs
    1.5 s)."""
    holds = [_longest_run_s(np.asarray(r.trace["abs_mode_fr_index"]) == ABS_HOLD, np.asarray(r.trace["time_s"]))
             for r in (run(name), run(name, baseline=True))]
    assert holds[0] > 2.0 and holds[0] > holds[1], holds


def test_45_mirror_of_the_twin_with_fr_abs_hold(run):
    """D, mechanism: the compensated car ends on the other side of the lane from the twin (the release's moment
    away from the blown side) while the intact FR sits in ONE uninterrupted ABS hold longer than the twin's longest
    (3.0 vs 1.4 s; status h item 8: a hold between the 10 % and 20 % thresholds has no time limit)."""
    on, none = run("s61_45"), run("s61_45", baseline=True)
    lo_on, lo_none = (float(np.asarray(r.trace["lane_offset_m"])[-1]) for r in (on, none))
    assert lo_on * lo_none < 0.0, (lo_on, lo_none)
    holds = [_longest_run_s(np.asarray(r.trace["abs_mode_fr_index"]) == ABS_HOLD, np.asarray(r.trace["time_s"]))
             for r in (on, none)]
    assert holds[0] > 2.0 > holds[1], holds


@pytest.mark.parametrize("name", ["s61_45"])
def test_abs_hold_limit_on_both_cars(run, name):
    """D, attribution: with I5's ABS hold time limit on both cars (platform ESP; the twin changes too) #45 is no
    violation (0.432 vs 0.483 m). Not shipped: I5's measurements (tire_blowout_findings.md I5)."""
    on = _dev(run(name, sets=ABS_HOLD_LIMIT))
    none = _dev(run(name, baseline=True, sets=ABS_HOLD_LIMIT))
    assert on <= none, f"{on:.3f} m vs none {none:.3f} m"


def test_8_outer_rear_abs_hold_across_the_detection(run):
    """B, mechanism: at 61 #8 the compensated car's outer rear RR enters an ABS hold before the detection (1.175 s, slip
    10-14 %, 45 bar) that lasts across it (to 1.86 s; detection 1.42 s); the twin's RR reaches the dump threshold
    and dumps (1.34 s, 46 -> 33 bar), and none of its RR holds in the same stretch is as long."""
    on, none = run("s61_8"), run("s61_8", baseline=True)
    t_on = np.asarray(on.trace["time_s"])
    t_det = float(t_on[np.argmax(np.asarray(on.trace["blowout_mode_index"]) != 0)])
    t0 = P61_8["brake.start_s"]

    def holds(r):
        """(start, end) of each uninterrupted RR ABS hold starting between the pedal and the detection + 0.5 s. Each
        run on its own time base (N1, session n, class A: to standstill the two runs end at different times)."""
        t = np.asarray(r.trace["time_s"])
        m = np.asarray(r.trace["abs_mode_rr_index"]) == ABS_HOLD
        out, k = [], 0
        while k < len(t):
            if m[k]:
                j = k
                while j < len(t) and m[j]:
                    j += 1
                if t0 <= t[k] <= t_det + 0.5:
                    out.append((float(t[k]), float(t[j - 1])))
                k = j
            else:
                k += 1
        return out
    h_on, h_none = holds(on), holds(none)
    across = [h for h in h_on if h[0] < t_det < h[1]]
    assert across, (t_det, h_on)
    longest_on = max(b - a for a, b in across)
    assert all(b - a < longest_on for a, b in h_none), (across, h_none)


def test_8_abs_hold_limit_on_both_cars_shrinks_the_gap(run):
    """B, attribution: with I5's ABS hold time limit on both cars the gap to the twin shrinks (measured 7.955 - 5.354
    = 2.601 m -> 5.080 - 4.788 = 0.292 m: still a violation, so item 8 is part of it, not all)."""
    gap = _dev(run("s61_8")) - _dev(run("s61_8", baseline=True))
    gap_a = _dev(run("s61_8", sets=ABS_HOLD_LIMIT)) - _dev(run("s61_8", baseline=True, sets=ABS_HOLD_LIMIT))
    assert gap_a < gap, (gap_a, gap)
