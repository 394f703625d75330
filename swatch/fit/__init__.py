"""Fits: thickness and spectral fits, Lab fits, matching, search, calibration."""
