"""Metrics: pure functions of a trace (see :mod:`vehicle_assist.metrics.common`)."""
from vehicle_assist.metrics.common import METRICS, Metric, compute_metrics, register
from vehicle_assist.metrics import hill_start  # noqa: F401  (registers the paper-000 metrics)
from vehicle_assist.metrics import hill_start_ehb  # noqa: F401  (registers the paper-001 metrics)
from vehicle_assist.metrics import brake_assist  # noqa: F401  (registers the paper-002 metrics)
from vehicle_assist.metrics import curve_shift  # noqa: F401  (registers the paper-003 metrics)
from vehicle_assist.metrics import blowout  # noqa: F401  (registers the paper-004 metrics)


def known_metric_names() -> list[str]:
    return sorted(METRICS)


__all__ = ["METRICS", "Metric", "compute_metrics", "register", "known_metric_names"]
