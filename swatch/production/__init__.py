"""Production: the finish specification of a colour (spec.json), its PDF card, and the QC of measured parts against it."""
