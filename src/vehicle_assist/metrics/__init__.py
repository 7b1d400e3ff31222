"""Metrics: pure functions of a trace (see :mod:`vehicle_assist.metrics.common`)."""
from vehicle_assist.metrics.common import METRICS, Metric, compute_metrics, register


def known_metric_names() -> list[str]:
    return sorted(METRICS)


__all__ = ["METRICS", "Metric", "compute_metrics", "register", "known_metric_names"]
