"""File formats: images (EXR/PNG/TIFF), PNG metadata, measurement files, coupon files."""
