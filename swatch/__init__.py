"""swatch: physics-based colour swatches for anodised titanium.

Thin-film interference of an anodic oxide on a metal, evaluated with the
half-vector model of Fujii et al. (IEICE Trans. Inf. & Syst. J102-D, 2019),
turned into spectra, CIELAB values, renders and catalog sheets.
"""

__version__ = "0.1.0"

import warnings as _warnings

# colour-science announces, on first use of some functions, that its plotting API needs
# Matplotlib. swatch never plots through colour-science; keep the CLI's output clean.
_warnings.filterwarnings("ignore", message='"Matplotlib" related API features are not available')
