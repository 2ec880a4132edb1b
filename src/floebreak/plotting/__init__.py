"""Figures: floe fields, breaking patterns, spectra."""
