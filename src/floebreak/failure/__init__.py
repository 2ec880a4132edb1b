"""Failure modes behind one interface, with a registry."""
