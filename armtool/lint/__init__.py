"""`armtool lint`: find the silent mistakes in robot descriptions that parsers accept."""
