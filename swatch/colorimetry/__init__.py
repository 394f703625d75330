"""Colorimetry: colorimeter (spectra to XYZ/Lab/sRGB), tolerances, appearance, colour names."""
