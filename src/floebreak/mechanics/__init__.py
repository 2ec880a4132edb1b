"""Mechanics: contact geometry and forces, failure-mode classification, Nevel wedge, fracture laws."""


def compile_kernels() -> None:
    """Compile the numba kernels (or load them from numba's on-disk cache) ahead of a run: contact, failure
    probes, classification, and the floe packing's energy (`floebreak.ice.packing`).

    The first use on a machine compiles for several seconds; `make` calls this at set-up, and benchmarks call
    it before timing so that their figures are the steady state (the one-off cost is reported separately).
    """
    import numpy as np
    import shapely

    from floebreak.ice import packing
    from floebreak.mechanics import classify, contact_kernel, polygon_kernel

    packing.compile_now()
    contact_kernel.compile_now()
    polygon_kernel.compile_now()
    classify.oriented_extent_m(shapely.box(0.0, 0.0, 1.0, 1.0), np.array([1.0, 0.0]))
