"""The one exception type the CLI turns into a one-line error message."""


class SwatchError(ValueError):
    """Bad input or an impossible request: the message says what was wrong and what is allowed.

    The one exception type of the library's refusals. Its message is one line that names the
    parameter (or, from the command line, the flag) and the allowed values or bounds; the CLI
    prints it as ``error: <message>`` and exits with status 2, leaving nothing half-written.

    Examples
    --------
    >>> from swatch.physics.model import check_thickness_nm
    >>> try:
    ...     check_thickness_nm(-5.0)
    ... except SwatchError as exc:
    ...     print("refused")
    refused
    """
