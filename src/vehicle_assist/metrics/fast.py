"""Compiled twins of the metrics, for batches: the same values, bit for bit, at a fraction of the cost.

:func:`vehicle_assist.metrics.compute_metrics` evaluates each metric with numpy on a (runs, samples) chunk;
each metric then makes several passes over the chunk and allocates temporaries. In a batch of 10,000 truck
variants that cost as much as a third of the kernel. Here each metric that has a twin is one compiled pass
per run over the channels (2-D float arrays, any strides: views into the trace buffer, no copies).

Every twin reproduces its numpy metric's arithmetic in the same order (numpy's pairwise summation for the
trapezoid integrals, ``numpy.gradient``'s non-uniform three-point formula, NaN propagation of ``np.min`` /
``np.max``), so the values are identical, not close; ``tests/metrics/test_fast_metrics.py`` compares both on
every shipped truck and EV scenario and on perturbed variants. A metric without a twin (or a trace without
the channels a twin reads) falls back to the numpy function, so new metrics stay correct, only slower.

All twins share one compiled signature family (float64 2-D arrays of any layout), so they compile once for
every vehicle layout (about 3 s, cached with the kernels and warmed by ``make setup``).
"""
from __future__ import annotations

import math
from collections.abc import Iterable

import numba as nb
import numpy as np

from vehicle_assist.metrics import common as C
from vehicle_assist.metrics.common import METRICS

_JIT = dict(cache=True, nogil=True, error_model="numpy")


# ------------------------------------------------------------------------------------------ primitives
@nb.njit(**_JIT)
def _pairwise_block(a, lo, n):
    """numpy's pairwise summation of a block of at most 128 entries (8 accumulators)."""
    if n < 8:
        res = -0.0
        for i in range(lo, lo + n):
            res += a[i]
        return res
    r0 = a[lo]
    r1 = a[lo + 1]
    r2 = a[lo + 2]
    r3 = a[lo + 3]
    r4 = a[lo + 4]
    r5 = a[lo + 5]
    r6 = a[lo + 6]
    r7 = a[lo + 7]
    i = 8
    stop = n - (n % 8)
    while i < stop:
        r0 += a[lo + i]
        r1 += a[lo + i + 1]
        r2 += a[lo + i + 2]
        r3 += a[lo + i + 3]
        r4 += a[lo + i + 4]
        r5 += a[lo + i + 5]
        r6 += a[lo + i + 6]
        r7 += a[lo + i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@nb.njit(**_JIT)
def _pairwise(a, lo, n):
    """numpy's pairwise summation of a[lo:lo + n] (``np.add.reduce`` on a contiguous float64 row): blocks of at
    most 128 summed by :func:`_pairwise_block`, halves (rounded to 8) added as a binary tree. The recursion of
    numpy's C code is an explicit stack here (numba cannot reload a cached recursive function)."""
    if n <= 128:
        return _pairwise_block(a, lo, n)
    los = np.empty(64, dtype=np.int64)
    ns = np.empty(64, dtype=np.int64)
    stage = np.zeros(64, dtype=np.int64)
    left = np.empty(64)
    sp = 0
    los[0] = lo
    ns[0] = n
    ret = 0.0
    while sp >= 0:
        m = ns[sp]
        if m <= 128:
            ret = _pairwise_block(a, los[sp], m)
            sp -= 1
            continue
        n2 = m // 2
        n2 -= n2 % 8
        if stage[sp] == 0:
            stage[sp] = 1
            sp += 1
            los[sp] = los[sp - 1]
            ns[sp] = n2
            stage[sp] = 0
        elif stage[sp] == 1:
            left[sp] = ret
            stage[sp] = 2
            sp += 1
            los[sp] = los[sp - 1] + n2
            ns[sp] = m - n2
            stage[sp] = 0
        else:
            ret = left[sp] + ret
            sp -= 1
    return ret


@nb.njit(**_JIT)
def _trapz_row(y, t, buf):
    """``np.trapezoid(y, t)``: sum of (dt * (y[i+1] + y[i])) / 2.0, summed pairwise as numpy does."""
    n = y.shape[0]
    if n < 2:
        return 0.0
    for i in range(n - 1):
        buf[i] = (t[i + 1] - t[i]) * (y[i + 1] + y[i]) / 2.0
    return _pairwise(buf, 0, n - 1)


@nb.njit(**_JIT, inline="always")
def _extreme(x, largest):
    """``np.max`` (``largest``) or ``np.min`` of a row: the first NaN propagates. Inlined with a constant
    ``largest``, so each use compiles to its own one-comparison loop."""
    m = x[0]
    for i in range(x.shape[0]):
        v = x[i]
        if v != v:
            return v
        if (v > m) if largest else (v < m):
            m = v
    return m


@nb.njit(**_JIT)
def _min(x):
    return _extreme(x, False)


@nb.njit(**_JIT)
def _max(x):
    return _extreme(x, True)


@nb.njit(**_JIT)
def _np_maximum(a, b):
    """np.maximum of two scalars (NaN propagates)."""
    if a != a or b != b:
        return a + b
    return a if a >= b else b


# ------------------------------------------------------------------------------------------ twins
# each takes (time_s 1-D, channel 2-D, ...) and fills out[r] for every run r of the chunk
@nb.njit(**_JIT)
def rollback_distance_m(t, pos, out):
    for r in range(pos.shape[0]):
        out[r] = _np_maximum(0.0, pos[r, 0] - _min(pos[r]))


@nb.njit(**_JIT)
def rollback_speed_mps(t, v, out):
    for r in range(v.shape[0]):
        out[r] = _np_maximum(0.0, -_min(v[r]))


@nb.njit(**_JIT)
def row_min(t, x, out):
    for r in range(x.shape[0]):
        out[r] = _min(x[r])


@nb.njit(**_JIT)
def row_max(t, x, out):
    for r in range(x.shape[0]):
        out[r] = _max(x[r])


@nb.njit(**_JIT)
def row_last(t, x, out):
    for r in range(x.shape[0]):
        out[r] = x[r, x.shape[1] - 1]


@nb.njit(**_JIT)
def max_at_least_half(t, x, out):
    for r in range(x.shape[0]):
        out[r] = 1.0 if _max(x[r]) >= 0.5 else 0.0


@nb.njit(**_JIT)
def max_above_half(t, x, out):
    for r in range(x.shape[0]):
        out[r] = 1.0 if _max(x[r]) > 0.5 else 0.0


@nb.njit(**_JIT)
def integral(t, y, out):
    buf = np.empty(max(y.shape[1], 1))
    for r in range(y.shape[0]):
        out[r] = _trapz_row(y[r], t, buf)


@nb.njit(**_JIT)
def park_brake_drag_energy_j(t, f, v, out):
    n = f.shape[1]
    power = np.empty(n)
    buf = np.empty(max(n, 1))
    for r in range(f.shape[0]):
        for i in range(n):
            power[i] = abs(f[r, i] * v[r, i])
        out[r] = _trapz_row(power, t, buf)


@nb.njit(**_JIT)
def _gradient_row(f, t, uniform, out):
    """``np.gradient(f, t)`` (edge_order 1) of one row."""
    n = f.shape[0]
    if uniform:
        dx = t[1] - t[0]
        for i in range(1, n - 1):
            out[i] = (f[i + 1] - f[i - 1]) / (2. * dx)
        out[0] = (f[1] - f[0]) / dx
        out[n - 1] = (f[n - 1] - f[n - 2]) / dx
        return
    for i in range(1, n - 1):
        dx1 = t[i] - t[i - 1]
        dx2 = t[i + 1] - t[i]
        a = -(dx2) / (dx1 * (dx1 + dx2))
        b = (dx2 - dx1) / (dx1 * dx2)
        c = dx1 / (dx2 * (dx1 + dx2))
        out[i] = a * f[i - 1] + b * f[i] + c * f[i + 1]
    out[0] = (f[1] - f[0]) / (t[1] - t[0])
    out[n - 1] = (f[n - 1] - f[n - 2]) / (t[n - 1] - t[n - 2])


@nb.njit(**_JIT)
def jerk_rows(t, filtered, held, has_held, out):
    """``filtered_jerk``: gradient over t of the filtered acceleration, 0 where held (rows of ``out``)."""
    n = t.shape[0]
    uniform = True
    d0 = t[1] - t[0]
    for i in range(1, n - 1):
        if t[i + 1] - t[i] != d0:
            uniform = False
            break
    for r in range(filtered.shape[0]):
        _gradient_row(filtered[r], t, uniform, out[r])
        if has_held:
            for i in range(n):
                if held[r, i] >= 0.5:
                    out[r, i] = 0.0


@nb.njit(**_JIT)
def jerk_stats(jerk, out_max, out_min, out_peak):
    for r in range(jerk.shape[0]):
        out_max[r] = _max(jerk[r])
        out_min[r] = _min(jerk[r])
        mx = abs(jerk[r, 0])
        nan = False
        for i in range(jerk.shape[1]):
            a = abs(jerk[r, i])
            if a != a:
                nan = True
                mx = a
                break
            if a > mx:
                mx = a
        out_peak[r] = mx


@nb.njit(**_JIT)
def launch_time_s(t, v, brake, has_brake, acc, has_acc, threshold, out):
    n = t.shape[0]
    for r in range(v.shape[0]):
        start = t[0]
        decided = False
        if has_brake:
            first = -1
            for i in range(n):
                if brake[r, i] >= C.PEDAL_APPLIED_FRAC:
                    first = i
                    break
            if first >= 0:
                rel = -1
                for i in range(first, n):
                    if not brake[r, i] >= C.PEDAL_APPLIED_FRAC:
                        rel = i
                        break
                start = t[rel] if rel >= 0 else np.nan
                decided = True
        if not decided and has_acc:
            for i in range(n):
                if acc[r, i] > C.PEDAL_APPLIED_FRAC:
                    start = t[i]
                    break
        if start != start:
            out[r] = np.nan
            continue
        res = np.nan
        for i in range(n):
            if v[r, i] >= threshold and t[i] >= start:
                res = t[i] - start
                break
        out[r] = res


@nb.njit(**_JIT)
def engine_speed_after_downshift_max_radps(t, g, w, window_s, out):
    """Twin of metrics.curve_shift.engine_speed_after_downshift_max_radps (Python ``max(last, np.max(w))``)."""
    n = t.shape[0]
    for r in range(g.shape[0]):
        last = 0.0
        best = np.nan
        before = g[r, 0]
        for k in range(1, n):
            if g[r, k] > 0 and g[r, k - 1] == 0:
                if g[r, k] < before:
                    m = np.nan
                    found = False
                    nan = False
                    lim = t[k] + window_s
                    for j in range(k, n):
                        if t[j] <= lim:
                            x = w[r, j]
                            if not found:
                                m = x
                                found = True
                            elif not nan and (x != x or x > m):
                                m = x
                            if x != x:
                                nan = True
                                m = x
                    if found:
                        best = m if m > last else last
                        last = best
                before = g[r, k]
            elif g[r, k] > 0:
                before = g[r, k]
        out[r] = best if math.isfinite(best) else 0.0


# ------------------------------------------------------------------------------------------ hill start (truck)
@nb.njit(**_JIT)
def park_release_phase_index(t, cap, f_t, f_i, tol, out):
    for r in range(cap.shape[0]):
        c0 = cap[r, 0]
        lim = c0 * (1.0 - 1e-9)
        i = -1
        for k in range(cap.shape[1]):
            if cap[r, k] < lim:
                i = k
                break
        if i < 0 or not c0 > 0.0:
            out[r] = np.nan
            continue
        ft = f_t[r, i]
        fi = f_i[r, i]
        out[r] = 2.0 if abs(ft - fi) <= tol * abs(fi) else (3.0 if ft > fi else 1.0)


@nb.njit(**_JIT)
def _release_and_load(ctrl, f_t, f_i, f_f, r):
    n = ctrl.shape[1]
    i_rel = -1
    for k in range(1, n):
        if ctrl[r, k] > 0.0 and ctrl[r, k - 1] <= 0.0:
            i_rel = k
            break
    i_load = -1
    for k in range(n):
        if f_t[r, k] >= f_i[r, k] + f_f[r, k]:
            i_load = k
            break
    return i_rel, i_load


@nb.njit(**_JIT)
def release_to_load_s(t, ctrl, f_t, f_i, f_f, out):
    for r in range(ctrl.shape[0]):
        i_rel, i_load = _release_and_load(ctrl, f_t, f_i, f_f, r)
        out[r] = t[i_load] - t[i_rel] if i_rel >= 0 and i_load >= 0 else np.nan


@nb.njit(**_JIT)
def release_margin_s(t, ctrl, f_t, f_i, f_f, lamp, out):
    for r in range(ctrl.shape[0]):
        i_rel, i_load = _release_and_load(ctrl, f_t, f_i, f_f, r)
        start = max(i_rel, 0)  # numpy: argmax of no release is 0
        i_off = -1
        for k in range(start, lamp.shape[1]):
            if lamp[r, k] < 0.5:
                i_off = k
                break
        if i_rel >= 0 and i_load >= 0 and i_off >= 0:
            out[r] = (t[i_off] - t[i_rel]) - (t[i_load] - t[i_rel])
        else:
            out[r] = np.nan


@nb.njit(**_JIT)
def _engage_span(mode, r, a, b):
    first = -1
    last = -1
    for k in range(mode.shape[1]):
        m = mode[r, k]
        if m == a or m == b:
            if first < 0:
                first = k
            last = k
    return first, last


@nb.njit(**_JIT)
def engage_rate_mean_per_s(t, mode, x, a, b, out):
    for r in range(mode.shape[0]):
        first, last = _engage_span(mode, r, a, b)
        if first >= 0 and last > first:
            out[r] = (x[r, last] - x[r, first]) / (t[last] - t[first])
        else:
            out[r] = np.nan


@nb.njit(**_JIT)
def engage_rate_law_mean_per_s(t, mode, x, a, b, buf, out):
    n = mode.shape[1]
    for r in range(mode.shape[0]):
        first, last = _engage_span(mode, r, a, b)
        if first < 0:
            last = n - 1  # numpy: argmax of the reversed all-False mask
            first = 0
        for k in range(n - 1):
            m = mode[r, k + 1]
            moving = (m == a or m == b) and abs(x[r, k + 1] - x[r, k]) > 1e-12
            buf[k] = (1.0 if moving else 0.0) * (t[k + 1] - t[k])
        active = _pairwise(buf, 0, n - 1) if n > 1 else 0.0
        found = _engage_span(mode, r, a, b)[0] >= 0
        if found and active > 0.0:
            out[r] = (x[r, last] - x[r, first]) / active
        else:
            out[r] = np.nan


# ------------------------------------------------------------------------------------------ hill start (EV)
@nb.njit(**_JIT)
def hold_force_ratio(t, mode, cap, f_i, hold, settle_s, out):
    n = t.shape[0]
    for r in range(mode.shape[0]):
        i0 = -1
        for k in range(n):
            if mode[r, k] == hold:
                i0 = k
                break
        if i0 < 0:
            out[r] = np.nan
            continue
        best = np.inf
        any_settled = False
        nan = False
        for k in range(n):
            if mode[r, k] == hold and t[k] >= t[i0] + settle_s:
                any_settled = True
                q = cap[r, k] / f_i[r, k]
                if q != q:
                    nan = True
                elif q < best:
                    best = q
        out[r] = (np.nan if nan else best) if any_settled else np.nan


@nb.njit(**_JIT)
def assist_jerk_peak_mps3(t, mode, v, jerk, hold, tail_s, vmax, out):
    n = t.shape[0]
    for r in range(mode.shape[0]):
        last = -1
        best = 0.0
        for k in range(n):
            if mode[r, k] >= hold:
                last = k
            window = last >= 0 and t[k] - t[max(last, 0)] <= tail_s and v[r, k] <= vmax
            val = abs(jerk[r, k]) if window else 0.0
            if val != val:
                best = val
                break
            if val > best or k == 0:
                best = val
        out[r] = best


@nb.njit(**_JIT)
def torque_above_driver_nm(t, req, drv, out):
    for r in range(req.shape[0]):
        m = req[r, 0] - drv[r, 0]
        for k in range(req.shape[1]):
            e = req[r, k] - drv[r, k]
            if e != e:
                m = e
                break
            if e > m:
                m = e
        out[r] = _np_maximum(m, 0.0)


@nb.njit(**_JIT)
def residual_pressure_at_p2_pa(t, f_t, f_i, p, out):
    for r in range(f_t.shape[0]):
        res = np.nan
        for k in range(f_t.shape[1]):
            if f_t[r, k] >= f_i[r, k] and f_i[r, k] > 0.0:
                res = p[r, k]
                break
        out[r] = res


@nb.njit(**_JIT)
def _after_start(t, v, r, start_speed):
    for k in range(v.shape[1]):
        if v[r, k] > start_speed:
            return k
    return -1


@nb.njit(**_JIT)
def time_after_start_s(t, v, x, start_speed, level, equal, out):
    """Time from the start (first sample with v > start_speed) to the first sample from there on where ``x``
    equals ``level`` (``equal``) or is below it; NaN without a start or such a sample. The twin of
    ``release_after_start_s`` (x = brake pressure below the released level) and ``assist_idle_after_start_s``
    (x = assist mode equal to IDLE)."""
    for r in range(v.shape[0]):
        i0 = _after_start(t, v, r, start_speed)
        res = np.nan
        for k in range(max(i0, 0), v.shape[1]):
            if (x[r, k] == level) if equal else (x[r, k] < level):
                if i0 >= 0:
                    res = t[k] - t[i0]
                break
        out[r] = res


@nb.njit(**_JIT)
def hold_entered_flag(t, mode, hold, out):
    for r in range(mode.shape[0]):
        f = 0.0
        for k in range(mode.shape[1]):
            if mode[r, k] == hold:
                f = 1.0
                break
        out[r] = f


@nb.njit(**_JIT)
def pressure_reapply_pa(t, mode, p, follow, out):
    for r in range(mode.shape[0]):
        running = np.inf
        best = 0.0
        for k in range(mode.shape[1]):
            fol = mode[r, k] == follow
            masked = p[r, k] if fol else np.inf
            if running != running or masked != masked:
                running = running + masked  # np.minimum propagates NaN
            elif masked < running:
                running = masked
            rise = p[r, k] - running if (fol and math.isfinite(running)) else 0.0
            if rise != rise:
                best = rise
                break
            if rise > best or k == 0:
                best = rise
        out[r] = best


# ------------------------------------------------------------------------------------------ dispatch
def _plain(fn, *channels):
    return lambda ch, t, out: fn(t, *[ch[c] for c in channels], out)


def _twins() -> dict:
    """name -> (channels the twin reads, callable(ch, t, out)); registered metrics only."""
    from vehicle_assist.functions import hill_start_amt as HA
    from vehicle_assist.functions import hill_start_ehb as HE
    from vehicle_assist.metrics import curve_shift as CS
    from vehicle_assist.metrics import hill_start as HS
    from vehicle_assist.metrics import hill_start_ehb as HEM

    tw = {
        "rollback_distance_m": (("position_m",), _plain(rollback_distance_m, "position_m")),
        "rollback_speed_mps": (("speed_mps",), _plain(rollback_speed_mps, "speed_mps")),
        "engine_speed_min_radps": (("engine_speed_radps",), _plain(row_min, "engine_speed_radps")),
        "engine_speed_peak_radps": (("engine_speed_radps",), _plain(row_max, "engine_speed_radps")),
        "engine_stalled_flag": (("engine_stalled_flag",), _plain(max_at_least_half, "engine_stalled_flag")),
        "clutch_slip_energy_j": (("clutch_slip_power_w",), _plain(integral, "clutch_slip_power_w")),
        "brake_drag_energy_j": (("brake_power_w",), _plain(integral, "brake_power_w")),
        "tyre_slip_energy_j": (("tyre_slip_power_w",), _plain(integral, "tyre_slip_power_w")),
        "peak_speed_mps": (("speed_mps",), _plain(row_max, "speed_mps")),
        "final_speed_mps": (("speed_mps",), _plain(row_last, "speed_mps")),
        "assist_refusal_code": (("assist_refusal_code",), _plain(row_max, "assist_refusal_code")),
        "valve_32_energized_flag": (("valve_32_energized_flag",), _plain(max_above_half, "valve_32_energized_flag")),
        "park_brake_drag_energy_j": (("park_brake_force_n", "speed_mps"),
                                     _plain(park_brake_drag_energy_j, "park_brake_force_n", "speed_mps")),
        "launch_time_s": (("speed_mps",), lambda ch, t, out: launch_time_s(
            t, ch["speed_mps"], ch.get("brake_pedal_frac", _DUMMY), "brake_pedal_frac" in ch,
            ch.get("accelerator_frac", _DUMMY), "accelerator_frac" in ch, C.LAUNCH_SPEED_MPS, out)),
        "park_release_phase_index": (("park_brake_capacity_n", "drive_force_n", "grade_resistance_n"),
                                     lambda ch, t, out: park_release_phase_index(
                                         t, ch["park_brake_capacity_n"], ch["drive_force_n"], ch["grade_resistance_n"],
                                         HS.PHASE_TOLERANCE_FRAC, out)),
        "release_to_load_s": (("relay_control_pressure_pa", "drive_force_n", "grade_resistance_n",
                               "rolling_resistance_capacity_n"),
                              _plain(release_to_load_s, "relay_control_pressure_pa", "drive_force_n",
                                     "grade_resistance_n", "rolling_resistance_capacity_n")),
        "release_margin_s": (("relay_control_pressure_pa", "drive_force_n", "grade_resistance_n",
                              "rolling_resistance_capacity_n", "park_lamp_flag"),
                             _plain(release_margin_s, "relay_control_pressure_pa", "drive_force_n",
                                    "grade_resistance_n", "rolling_resistance_capacity_n", "park_lamp_flag")),
        "engage_rate_mean_per_s": (("hsa_mode_index", "clutch_command_frac"), lambda ch, t, out: engage_rate_mean_per_s(
            t, ch["hsa_mode_index"], ch["clutch_command_frac"], float(HA.ENGAGE_HELD), float(HA.ENGAGE_RELEASING), out)),
        "engage_rate_law_mean_per_s": (("hsa_mode_index", "clutch_command_frac"),
                                       lambda ch, t, out: engage_rate_law_mean_per_s(
                                           t, ch["hsa_mode_index"], ch["clutch_command_frac"], float(HA.ENGAGE_HELD),
                                           float(HA.ENGAGE_RELEASING), np.empty(max(len(t), 1)), out)),
        "engine_speed_after_downshift_max_radps": (("gear_index", "engine_speed_radps"),
                                                   lambda ch, t, out: engine_speed_after_downshift_max_radps(
                                                       t, ch["gear_index"], ch["engine_speed_radps"],
                                                       CS.AFTER_SHIFT_WINDOW_S, out)),
        "hold_force_ratio": (("hsa_mode_index", "service_brake_capacity_n", "grade_resistance_n"),
                             lambda ch, t, out: hold_force_ratio(t, ch["hsa_mode_index"], ch["service_brake_capacity_n"],
                                                                 ch["grade_resistance_n"], float(HE.HOLD), HEM.SETTLE_S, out)),
        "torque_above_driver_nm": (("motor_torque_request_nm", "driver_torque_request_nm"),
                                   _plain(torque_above_driver_nm, "motor_torque_request_nm", "driver_torque_request_nm")),
        "residual_pressure_at_p2_pa": (("drive_force_n", "grade_resistance_n", "brake_pressure_pa"),
                                       _plain(residual_pressure_at_p2_pa, "drive_force_n", "grade_resistance_n",
                                              "brake_pressure_pa")),
        "release_after_start_s": (("speed_mps", "brake_pressure_pa"), lambda ch, t, out: time_after_start_s(
            t, ch["speed_mps"], ch["brake_pressure_pa"], HEM.START_SPEED_MPS, HEM.RELEASED_PA, False, out)),
        "assist_idle_after_start_s": (("speed_mps", "hsa_mode_index"), lambda ch, t, out: time_after_start_s(
            t, ch["speed_mps"], ch["hsa_mode_index"], HEM.START_SPEED_MPS, float(HE.IDLE), True, out)),
        "hold_entered_flag": (("hsa_mode_index",), lambda ch, t, out: hold_entered_flag(
            t, ch["hsa_mode_index"], float(HE.HOLD), out)),
        "pressure_reapply_pa": (("hsa_mode_index", "brake_pressure_pa"), lambda ch, t, out: pressure_reapply_pa(
            t, ch["hsa_mode_index"], ch["brake_pressure_pa"], float(HE.FOLLOW), out)),
    }
    # a twin stands for the metric registered under its name only while that is still the function it copies
    origin = {
        "rollback_distance_m": C.rollback_distance_m, "rollback_speed_mps": C.rollback_speed_mps,
        "engine_speed_min_radps": C.engine_speed_min_radps, "engine_speed_peak_radps": C.engine_speed_peak_radps,
        "engine_stalled_flag": C.engine_stalled_flag, "clutch_slip_energy_j": C.clutch_slip_energy_j,
        "brake_drag_energy_j": C.brake_drag_energy_j, "tyre_slip_energy_j": HS.tyre_slip_energy_j,
        "peak_speed_mps": C.peak_speed_mps, "final_speed_mps": C.final_speed_mps,
        "assist_refusal_code": METRICS["assist_refusal_code"].function,
        "valve_32_energized_flag": HS.valve_32_energized_flag, "park_brake_drag_energy_j": HS.park_brake_drag_energy_j,
        "launch_time_s": C.launch_time_s, "park_release_phase_index": HS.park_release_phase_index,
        "release_to_load_s": HS.release_to_load_s, "release_margin_s": HS.release_margin_s,
        "engage_rate_mean_per_s": HS.engage_rate_mean_per_s, "engage_rate_law_mean_per_s": HS.engage_rate_law_mean_per_s,
        "engine_speed_after_downshift_max_radps": CS.engine_speed_after_downshift_max_radps,
        "hold_force_ratio": HEM.hold_force_ratio, "torque_above_driver_nm": HEM.torque_above_driver_nm,
        "residual_pressure_at_p2_pa": HEM.residual_pressure_at_p2_pa, "release_after_start_s": HEM.release_after_start_s,
        "assist_idle_after_start_s": HEM.assist_idle_after_start_s, "hold_entered_flag": HEM.hold_entered_flag,
        "pressure_reapply_pa": HEM.pressure_reapply_pa,
    }
    return {k: v for k, v in tw.items() if k in METRICS and METRICS[k].function is origin.get(k)}


_DUMMY = np.zeros((1, 1))
_TWINS: dict | None = None
JERK_METRICS = ("jerk_filtered_max_mps3", "jerk_filtered_min_mps3", "jerk_filtered_peak_mps3", "assist_jerk_peak_mps3")


def twins() -> dict:
    global _TWINS
    if _TWINS is None:
        _TWINS = _twins()
    return _TWINS


def _jerk(ch: dict, t: np.ndarray) -> np.ndarray | None:
    """``metrics.common.filtered_jerk`` of every run of the chunk (the filter: the numba biquad it uses)."""
    if len(t) < 3:
        return None
    dt_s = float(np.median(np.diff(t)))
    if not dt_s > 0.0 or not C.JERK_FILTER_CUTOFF_HZ < 0.5 / dt_s:
        return None  # the unusual cases: left to the numpy metric
    b, a = C.butter2_lowpass(C.JERK_FILTER_CUTOFF_HZ, 1.0 / dt_s)
    accel = ch["accel_mps2"]
    filtered = C._biquad_rows(b, a, np.asarray(accel, dtype=np.float64))  # the signature the numpy metric uses
    out = np.empty_like(filtered)
    held = ch.get("vehicle_held_flag", _DUMMY)
    jerk_rows(t, filtered, held, "vehicle_held_flag" in ch, out)
    return out


# optional channels a twin reads when the trace has them (besides those in its entry)
_EXTRA_READS = {"launch_time_s": ("brake_pedal_frac", "accelerator_frac"),
                "jerk_filtered_max_mps3": ("accel_mps2", "vehicle_held_flag"),
                "jerk_filtered_min_mps3": ("accel_mps2", "vehicle_held_flag"),
                "jerk_filtered_peak_mps3": ("accel_mps2", "vehicle_held_flag"),
                "assist_jerk_peak_mps3": ("accel_mps2", "vehicle_held_flag", "hsa_mode_index", "speed_mps")}


def plan(channels: Iterable[str], names: Iterable[str] | None = None) -> tuple[list[str], list[str]]:
    """(metrics to compute, channels they read) for a trace with ``channels``: with ``names`` None, every
    registered metric the channels support (as :func:`compute_metrics`); all channels if a metric has no twin."""
    present = set(channels) | {"time_s"}
    if names is None:
        selected = [n for n, m in METRICS.items() if all(c in present for c in m.requires)]
    else:
        selected = list(names)
    tw = twins()
    reads: set[str] = set()
    for name in selected:
        if name in tw:
            reads |= set(tw[name][0])
        elif name in _EXTRA_READS and name in METRICS and name != "assist_jerk_peak_mps3":
            pass
        elif name == "assist_jerk_peak_mps3" and name in METRICS:
            pass
        else:
            return selected, [c for c in channels if c != "time_s"]
        reads |= set(_EXTRA_READS.get(name, ()))
    return selected, [c for c in channels if c in reads and c != "time_s"]


@nb.njit(**_JIT)
def gather(x, m, n, cols, out):
    """out[c, r, :n] = x[r, :n, cols[c]]: the channels of a (runs, samples, fields) float view of the trace rows,
    made contiguous in one sequential pass (each record read once, not once per metric)."""
    for r in range(m):
        for k in range(n):
            for c in range(cols.shape[0]):
                out[c, r, k] = x[r, k, cols[c]]


def compute_metrics_fast(ch: dict[str, np.ndarray], t: np.ndarray, names: Iterable[str] | None = None,
                         fallback=None) -> dict[str, np.ndarray]:
    """Metrics of a chunk of runs: ``ch`` channel -> (runs, samples) float64 arrays (views are fine), ``t`` the
    shared time base. Same names and values as ``compute_metrics(Trace(ch))`` (one array per metric); metrics
    without a twin are computed by ``fallback(names)`` (default: the numpy functions on a batch Trace)."""
    from vehicle_assist.core.trace import Trace

    if names is None:
        present = {**ch, "time_s": t}
        selected = [n for n, m in METRICS.items() if all(c in present for c in m.requires)]
    else:
        selected = list(names)
    if not selected:
        return {}
    runs = next(iter(v.shape[0] for k, v in ch.items() if k != "time_s" and np.ndim(v) == 2), None)
    if runs is None:  # no channel read (not expected: every metric reads one): the numpy path says what is missing
        from vehicle_assist.metrics.common import compute_metrics

        return compute_metrics(Trace({**ch, "time_s": t}), selected)
    tw = twins()
    out: dict[str, np.ndarray] = {}
    rest: list[str] = []
    jerk = None
    for name in selected:
        entry = tw.get(name)
        if name in JERK_METRICS and "accel_mps2" in ch:
            if jerk is None:
                jerk = _jerk(ch, t)
                if jerk is None:
                    jerk = False
            if jerk is False:
                rest.append(name)
                continue
            if name == "assist_jerk_peak_mps3":
                if METRICS[name].function is not __import__(
                        "vehicle_assist.metrics.hill_start_ehb", fromlist=["x"]).assist_jerk_peak_mps3:
                    rest.append(name)
                    continue
                from vehicle_assist.functions import hill_start_ehb as HE
                from vehicle_assist.metrics import hill_start_ehb as HEM

                o = np.empty(runs)
                assist_jerk_peak_mps3(t, ch["hsa_mode_index"], ch["speed_mps"], jerk, float(HE.HOLD),
                                      HEM.ASSIST_JERK_TAIL_S, HEM.START_PHASE_MAX_SPEED_MPS, o)
                out[name] = o + 0.0
                continue
            if name not in out:
                mx, mn, pk = np.empty(runs), np.empty(runs), np.empty(runs)
                jerk_stats(jerk, mx, mn, pk)
                out["jerk_filtered_max_mps3"], out["jerk_filtered_min_mps3"], out["jerk_filtered_peak_mps3"] = \
                    mx + 0.0, mn + 0.0, pk + 0.0
            continue
        if entry is None or not all(c in ch for c in entry[0]):
            rest.append(name)
            continue
        o = np.empty(runs)
        entry[1](ch, t, o)
        out[name] = o + 0.0
    if rest:
        if fallback is not None:
            more = fallback(rest)
        else:
            from vehicle_assist.metrics.common import compute_metrics

            more = compute_metrics(Trace({**ch, "time_s": t}), rest)
        out.update({k: np.broadcast_to(np.asarray(v, dtype=np.float64), (runs,)) for k, v in more.items()})
    return {name: out[name] for name in selected}
