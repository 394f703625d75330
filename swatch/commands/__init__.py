"""click subcommands of ``swatch`` (thin: parse, call the library, report)."""
