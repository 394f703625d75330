"""The one exception type the CLI turns into a one-line error message."""


class SwatchError(ValueError):
    """Bad input or an impossible request: the message says what was wrong and what is allowed.

    The CLI prints ``error: <message>`` on one line and exits with status 2.
    """
