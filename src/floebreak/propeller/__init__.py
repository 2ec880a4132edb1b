"""Propeller–ice loads: cusp boxes, FEM interpolation, spectra, ice-class rule."""
