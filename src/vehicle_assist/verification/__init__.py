"""Verification: operating envelopes (data), requirements as STL formulas (rtamt), falsification search
(CMA-ES / random), coverage and sensitivity studies, and the envelope studies of ``reproduce``.

See docs/verification.md."""
