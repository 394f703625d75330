"""Reports: figures (raster drawing), text reports, the calibration report."""
