"""Physics: optics (Airy thin film), geometry, microfacet, Rayleigh, materials, the half-vector model, process profiles."""
