"""Propeller ice torque → shaft torque: blade-impact excitation in time and a torsional shaft-line model.

`excitation` builds the propeller load torque Q(t) (mean hydrodynamic torque plus blade-impact ice torque,
physics-notes §7.3); `line` describes the shaft line (lumped inertias and shaft stiffnesses, built-in
``agulhas_ii``) and assembles it with openTorsion; `response` computes the shaft torque at a measurement
station; `analysis` ties them together for the cusps of a run. See docs/shaft.md.
"""
