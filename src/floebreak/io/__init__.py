"""Input and output: atomic writes, GeoParquet, provenance."""
