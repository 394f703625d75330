"""Calibrate a line's process profile from its test coupons (``swatch calibrate``).

Model (:mod:`swatch.fit.calibration.model`): a coupon anodised at ``voltage_V`` carries a film grown
by the line's growth law (linear, ``offset_nm + nm_per_V × voltage_V``, or two slopes with a knee
voltage, continuous at the knee), of a film table whose index's real part is scaled by
``film_index_scale``, on a substrate table, with a proportional thickness spread
(``spread_fraction``); its colour is the half-vector model's at the measuring geometry (default
45°:0°, D65, 10°).

Search: for every film × substrate table pair of the base profile's materials (or only the base's
pair when ``--film``/``--substrate`` fix them, or when fewer than ``COUPONS_FOR_TABLES`` coupons
are left to choose among them), the interference order is found by a global grid over the growth
law (each coupon's colour looked up in a thickness → CIELAB table), refined robustly (soft-L1, so a
mislabelled coupon cannot pull the line); coupons whose ΔE2000 stays far above the others' (over
``max(OUTLIER_MIN_DE00, 3 × 1.4826 × median)``) are outliers. Then, on the other coupons, the nested
models are fitted one parameter group at a time — growth law, + film index scale, + spread,
+ knee — each kept only when it lowers the leave-one-out (held-out) mean ΔE2000 by 5 % or more and
the coupons determine it (standard error small, enough coupons on each side of a knee). The table
pairs are ranked by that held-out mean: the first is the winner, written with its evidence
(``[calibration]``). Uncertainties are the standard errors of the final least-squares fit
(Gauss–Newton covariance scaled by the residual variance), in the profile's own parameters.
Measured thicknesses (``thickness_nm`` column) join the fit as residuals of ``THICKNESS_SIGMA_NM``.

Data that cannot determine a parameter are refused in one line: fewer than two coupons, all
coupons at one voltage.

Modules: :mod:`~swatch.fit.calibration.table` (the colour tables), :mod:`~swatch.fit.calibration.model`
(the model, its fit and covariance), :mod:`~swatch.fit.calibration.search` (interference order and
robust screening of every table pair), :mod:`~swatch.fit.calibration.leave_one_out` (held-out ΔE2000),
:mod:`~swatch.fit.calibration.selection` (outliers and the nested models),
:mod:`~swatch.fit.calibration.result` (the report), :mod:`~swatch.fit.calibration.procedure` (all of it:
:func:`calibrate`).
"""
from __future__ import annotations

from swatch.fit.calibration.model import THICKNESS_SIGMA_NM
from swatch.fit.calibration.procedure import COUPONS_FOR_TABLES, calibrate
from swatch.fit.calibration.result import Calibration
from swatch.fit.calibration.selection import OUTLIER_MIN_DE00
from swatch.fit.calibration.table import clear_tables

__all__ = ["Calibration", "calibrate", "clear_tables", "OUTLIER_MIN_DE00", "THICKNESS_SIGMA_NM", "COUPONS_FOR_TABLES"]
