"""Mechanics: contact geometry and forces, failure-mode classification, Nevel wedge, fracture laws."""
