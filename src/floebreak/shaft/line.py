"""Torsional shaft-line model: lumped inertias joined by shaft springs and dampers (docs/shaft.md).

Elements are listed from the motor (index 0) to the propeller (last). Element i has an inertia J_i [kg·m²]
and, except the propeller, the shaft to element i+1 with stiffness k_i [N·m/rad] and damping ratio ζ_i.
The shaft damping coefficient is the one that gives the two-inertia oscillator (J_i, J_{i+1}, k_i) the
modal damping ratio ζ_i:

    c_i = 2 ζ_i √(k_i J_i J_{i+1} / (J_i + J_{i+1}))            [N·m·s/rad]

The propeller inertia includes entrained water: J_prop = J_dry (1 + f_w), f_w = ``entrained_water_fraction``.
In the time domain the motor is speed-controlled: its PI speed controller acts as a torsional spring
k_g = J_tot ω_g² and damper c_g = 2 ζ_g J_tot ω_g to ground at the motor (ω_g = 2π·bandwidth), so a
constant propeller torque is carried through every shaft (static gain 1). With ``hydrodynamic_damping``
the propeller torque's speed dependence Q ∝ ω² adds c_p = dQ/dω = 2 Q_mean/ω at the propeller.
Natural frequencies and mode shapes are those of the free-free line (no controller, no water damping).
"""

from __future__ import annotations

import math
import os
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from floebreak.errors import InputError, require_range
from floebreak.io.text_files import read_text_file
from floebreak.io.toml_text import loads_toml
from floebreak.propeller.spec import MAX_PROPELLER_RPM

BUILTIN_LINES = ("agulhas_ii",)
G_STEEL_PA = 80e9  # shear modulus of shaft steel


def solid_shaft_stiffness_n_m_per_rad(diameter_m: float, length_m: float, shear_modulus_pa=G_STEEL_PA):
    """k = G·π d⁴/(32 L) of a solid circular shaft [N·m/rad]."""
    return shear_modulus_pa * math.pi * diameter_m**4 / (32.0 * length_m)


# Built-in PSRV S.A. Agulhas II port shaft line. Every value: its source, or "assumed" (docs/shaft.md table).
AGULHAS_II = {
    "name": "agulhas_ii",
    "rpm": 140.0,  # thesis §6.1.2
    "rated_power_w": 4.5e6,  # ≈ 2 × 4.5 MW motors: physics-notes §6.1 [recalled, medium]
    "entrained_water_fraction": 0.25,  # assumed (typical 0.2-0.3 of the dry inertia for open CP propellers)
    "speed_control_bandwidth_hz": 0.5,  # assumed
    "speed_control_damping_ratio": 0.7,  # assumed
    "hydrodynamic_damping": True,
    "default_station": "intermediate_shaft",  # assumed: strain gauges on the shaft inboard (thesis Fig. 34)
    "elements": [
        {
            "name": "motor",
            "inertia_kg_m2": 20000.0,  # assumed: rotor of a ≈ 4.5 MW, 140 rpm direct-drive motor
            "shaft": "intermediate_shaft",
            # assumed: solid steel, d = 0.45 m, L = 15 m
            "stiffness_n_m_per_rad": round(solid_shaft_stiffness_n_m_per_rad(0.45, 15.0), -3),
            "damping_ratio": 0.02,  # assumed
        },
        {
            "name": "thrust_bearing",
            "inertia_kg_m2": 1500.0,  # assumed: thrust collar, couplings and half of both shafts
            "shaft": "propeller_shaft",
            # assumed: solid steel, d = 0.55 m, L = 12 m
            "stiffness_n_m_per_rad": round(solid_shaft_stiffness_n_m_per_rad(0.55, 12.0), -3),
            "damping_ratio": 0.02,  # assumed
        },
        {
            "name": "propeller",
            "inertia_kg_m2": 7500.0,  # assumed: dry CP propeller, D = 4.3 m (thesis), Z = 4 (notes §7.1)
        },
    ],
}


@dataclass(frozen=True)
class ShaftElement:
    """One lumped inertia and the shaft to the next element (None for the propeller)."""

    name: str
    inertia_kg_m2: float
    stiffness_n_m_per_rad: float | None = None
    damping_ratio: float | None = None
    shaft: str | None = None


@dataclass(frozen=True)
class ShaftLine:
    """A validated shaft line (module docstring). Build with `shaft_line_from_dict` or `load_shaft_line`."""

    name: str
    elements: tuple[ShaftElement, ...]
    rpm: float
    rated_power_w: float | None = None
    mean_torque_n_m: float | None = None
    entrained_water_fraction: float = 0.0
    speed_control_bandwidth_hz: float = 0.5
    speed_control_damping_ratio: float = 0.7
    hydrodynamic_damping: bool = True
    default_station: str | None = None
    source: str = field(default="", compare=False)

    @property
    def stations(self) -> tuple[str, ...]:
        """Names of the shafts (measurement stations), motor side first."""
        return tuple(e.shaft for e in self.elements[:-1])

    @property
    def inertias_kg_m2(self) -> np.ndarray:
        """J_i, the propeller's with entrained water J_dry (1 + f_w)."""
        j = np.array([e.inertia_kg_m2 for e in self.elements], dtype=float)
        j[-1] *= 1.0 + self.entrained_water_fraction
        return j

    @property
    def stiffnesses_n_m_per_rad(self) -> np.ndarray:
        return np.array([e.stiffness_n_m_per_rad for e in self.elements[:-1]], dtype=float)

    @property
    def damping_n_m_s_per_rad(self) -> np.ndarray:
        """c_i = 2 ζ_i √(k_i J_i J_{i+1}/(J_i + J_{i+1})) (module docstring)."""
        j = self.inertias_kg_m2
        zeta = np.array([e.damping_ratio for e in self.elements[:-1]], dtype=float)
        reduced = j[:-1] * j[1:] / (j[:-1] + j[1:])
        return 2.0 * zeta * np.sqrt(self.stiffnesses_n_m_per_rad * reduced)

    def mean_torque(self) -> float:
        """Mean hydrodynamic torque [N·m]: the given one, else P/(2π n) at the line's rpm."""
        if self.mean_torque_n_m is not None:
            return float(self.mean_torque_n_m)
        return float(self.rated_power_w) / (2.0 * math.pi * self.rpm / 60.0)

    def station_index(self, station: str | None) -> int:
        """Index of the shaft `station` (default: the line's default station, else the first shaft)."""
        name = station if station is not None else (self.default_station or self.stations[0])
        if name not in self.stations:
            raise InputError(
                "station",
                f"no station {name!r} in shaft line {self.name!r}",
                value=name,
                allowed=", ".join(self.stations),
            )
        return self.stations.index(name)


def _element(data, i: int, last: bool, key: str) -> ShaftElement:
    where = f"{key}.elements[{i}]"
    if not isinstance(data, dict):
        raise InputError(where, "is not a table", allowed="a [[shaft_line.elements]] table")
    known = {"name", "inertia_kg_m2", "stiffness_n_m_per_rad", "damping_ratio", "shaft"}
    unknown = sorted(set(data) - known)
    if unknown:
        raise InputError(f"{where}.{unknown[0]}", "unknown key", allowed=", ".join(sorted(known)))
    name = data.get("name", f"element_{i}")
    if not isinstance(name, str) or not name:
        raise InputError(f"{where}.name", f"{name!r} is not a name", allowed="a non-empty string")
    inertia = require_range(f"{where}.inertia_kg_m2", data.get("inertia_kg_m2"), low=0.0, unit="kg m^2")
    if last:
        extra = [k for k in ("stiffness_n_m_per_rad", "damping_ratio", "shaft") if k in data]
        if extra:
            raise InputError(f"{where}.{extra[0]}", "the last element is the propeller: no shaft follows it")
        return ShaftElement(name, inertia)
    stiffness = require_range(
        f"{where}.stiffness_n_m_per_rad", data.get("stiffness_n_m_per_rad"), low=0.0, unit="N m/rad"
    )
    zeta = require_range(
        f"{where}.damping_ratio",
        data.get("damping_ratio", 0.0),
        low=0.0,
        high=1.0,
        low_inclusive=True,
        high_inclusive=False,
    )
    return ShaftElement(name, inertia, stiffness, zeta, str(data.get("shaft", f"{name}_shaft")))


_LINE_KEYS = {
    "name",
    "rpm",
    "rated_power_w",
    "mean_torque_n_m",
    "entrained_water_fraction",
    "speed_control_bandwidth_hz",
    "speed_control_damping_ratio",
    "hydrodynamic_damping",
    "default_station",
    "elements",
}


def shaft_line_from_dict(data: dict, key: str = "shaft_line", source: str = "") -> ShaftLine:
    """Validate a ``[shaft_line]`` table (docs/shaft.md); every error names its dotted key."""
    unknown = sorted(set(data) - _LINE_KEYS)
    if unknown:
        raise InputError(f"{key}.{unknown[0]}", "unknown key", allowed=", ".join(sorted(_LINE_KEYS)))
    raw = data.get("elements")
    if not isinstance(raw, list) or len(raw) < 2:
        raise InputError(
            f"{key}.elements",
            f"{0 if not isinstance(raw, list) else len(raw)} element(s)",
            allowed="at least 2 elements, motor first and propeller last",
        )
    elements = tuple(_element(e, i, i == len(raw) - 1, key) for i, e in enumerate(raw))
    stations = [e.shaft for e in elements[:-1]]
    if len(set(stations)) < len(stations) or len({e.name for e in elements}) < len(elements):
        raise InputError(f"{key}.elements", "element names and shaft names must be unique")
    power, torque = data.get("rated_power_w"), data.get("mean_torque_n_m")
    if (power is None) == (torque is None):
        raise InputError(
            f"{key}.rated_power_w",
            "give exactly one of rated_power_w and mean_torque_n_m",
            allowed="rated power [W] with rpm, or a mean torque [N m]",
        )
    line = ShaftLine(
        name=str(data.get("name", "custom")),
        elements=elements,
        rpm=require_range(f"{key}.rpm", data.get("rpm"), low=0.0, high=MAX_PROPELLER_RPM, unit="1/min"),
        rated_power_w=None
        if power is None
        else require_range(f"{key}.rated_power_w", power, low=0.0, unit="W"),
        mean_torque_n_m=None
        if torque is None
        else require_range(f"{key}.mean_torque_n_m", torque, low=0.0, low_inclusive=True, unit="N m"),
        entrained_water_fraction=require_range(
            f"{key}.entrained_water_fraction",
            data.get("entrained_water_fraction", 0.0),
            low=0.0,
            low_inclusive=True,
            high=2.0,
        ),
        speed_control_bandwidth_hz=require_range(
            f"{key}.speed_control_bandwidth_hz",
            data.get("speed_control_bandwidth_hz", 0.5),
            low=0.0,
            unit="Hz",
        ),
        speed_control_damping_ratio=require_range(
            f"{key}.speed_control_damping_ratio",
            data.get("speed_control_damping_ratio", 0.7),
            low=0.0,
            high=10.0,
        ),
        hydrodynamic_damping=_boolean(data.get("hydrodynamic_damping", True), f"{key}.hydrodynamic_damping"),
        default_station=data.get("default_station"),
        source=source,
    )
    if line.default_station is not None and str(line.default_station) not in line.stations:
        raise InputError(
            f"{key}.default_station", f"no shaft {line.default_station!r}", allowed=", ".join(line.stations)
        )
    return line


def _boolean(value, key: str) -> bool:
    if not isinstance(value, bool):
        raise InputError(key, f"{value!r} is not a boolean", value=value, allowed="true or false")
    return value


def builtin_shaft_line(name: str) -> dict:
    """A copy of the built-in line's ``[shaft_line]`` table (``agulhas_ii``)."""
    if name != "agulhas_ii":
        raise InputError("shaft_line", f"no built-in shaft line {name!r}", allowed=", ".join(BUILTIN_LINES))
    return {**AGULHAS_II, "elements": [dict(e) for e in AGULHAS_II["elements"]]}


def _merge(base: dict, table: dict, key: str) -> dict:
    """`table` over `base`; ``element_overrides.NAME`` changes keys of the named base element."""
    overrides = table.pop("element_overrides", {})
    merged = {**base, **table}
    if "elements" in table:
        return merged
    elements = [dict(e) for e in base["elements"]]
    names = [e["name"] for e in elements]
    for name, change in overrides.items():
        if name not in names:
            raise InputError(f"{key}.element_overrides.{name}", "no such element", allowed=", ".join(names))
        elements[names.index(name)].update(change)
    merged["elements"] = elements
    return merged


def load_shaft_line(spec: str | os.PathLike[str]) -> ShaftLine:
    """A built-in name (``agulhas_ii``) or a TOML file with a ``[shaft_line]`` table. The table may start
    from a built-in line (``base = "agulhas_ii"``) and override its keys and, in
    ``[shaft_line.element_overrides.NAME]``, keys of its elements."""
    if str(spec) in BUILTIN_LINES:
        return shaft_line_from_dict(builtin_shaft_line(str(spec)), source=f"built-in {spec}")
    path = Path(spec)
    if path.suffix.lower() != ".toml" or not path.is_file():
        raise InputError(
            "shaft_line",
            f"{str(spec)!r} is neither a built-in line nor a TOML file",
            value=str(spec),
            allowed=", ".join(BUILTIN_LINES) + ", or FILE.toml",
        )
    text = read_text_file(path, "shaft_line", encoding="utf-8-sig")
    try:
        data = loads_toml(text, "shaft_line", str(path))
    except tomllib.TOMLDecodeError as error:
        raise InputError("shaft_line", f"cannot read {str(path)!r}: {error}", value=str(path)) from None
    table = data.get("shaft_line")
    if not isinstance(table, dict):
        raise InputError("shaft_line", f"{str(path)!r} has no [shaft_line] table", value=str(path))
    table = dict(table)
    base = table.pop("base", None)
    if base is not None:
        table = _merge(builtin_shaft_line(str(base)), table, "shaft_line")
    elif "element_overrides" in table:
        raise InputError("shaft_line.element_overrides", "needs base = a built-in line")
    return shaft_line_from_dict(table, source=str(path))


def with_operating_point(line: ShaftLine, rpm: float | None = None, mean_torque_n_m: float | None = None):
    """The line at another rpm and/or mean torque (validated: rpm > 0, torque ≥ 0)."""
    changes: dict = {}
    if rpm is not None:
        changes["rpm"] = require_range("rpm", rpm, low=0.0, high=MAX_PROPELLER_RPM, unit="1/min")
    if mean_torque_n_m is not None:
        changes["mean_torque_n_m"] = require_range(
            "mean_torque_n_m", mean_torque_n_m, low=0.0, low_inclusive=True, unit="N m"
        )
        changes["rated_power_w"] = None
    return replace(line, **changes)


def assembly(line: ShaftLine, *, time_domain: bool = True):
    """openTorsion Assembly of `line`: a Disk per inertia, a Shaft (k, c, no inertia) per shaft.

    `time_domain` adds the motor's speed controller (spring and damper to ground at the motor) and, with
    ``hydrodynamic_damping``, the propeller's c_p = 2 Q_mean/ω; without them the line is free-free.
    """
    import opentorsion as ot

    j = line.inertias_kg_m2
    k, c = line.stiffnesses_n_m_per_rad, line.damping_n_m_s_per_rad
    shafts = [ot.Shaft(i, i + 1, k=float(k[i]), c=float(c[i]), I=0.0) for i in range(k.size)]
    ground_k, ground_c, prop_c = np.zeros(j.size), np.zeros(j.size), 0.0
    if time_domain:
        omega_g = 2.0 * math.pi * line.speed_control_bandwidth_hz
        ground_k[0] = j.sum() * omega_g**2
        ground_c[0] = 2.0 * line.speed_control_damping_ratio * j.sum() * omega_g
        if line.hydrodynamic_damping:
            prop_c = 2.0 * line.mean_torque() / (2.0 * math.pi * line.rpm / 60.0)
    disks = [
        ot.Disk(
            i,
            I=float(j[i]),
            k=float(ground_k[i]),
            c=float(ground_c[i] + (prop_c if i == j.size - 1 else 0.0)),
        )
        for i in range(j.size)
    ]
    return ot.Assembly(shafts, disk_elements=disks)


@dataclass(frozen=True)
class Modes:
    """Free-free torsional modes (rigid-body mode left out), lowest first."""

    frequency_hz: np.ndarray  # undamped natural frequencies
    shapes: np.ndarray  # (mode, element) angle amplitudes, largest |value| = 1 and positive
    damping_ratio: np.ndarray  # of the damped free-free line (shaft dampers only)


def modal_analysis(line: ShaftLine) -> Modes:
    """Natural frequencies, mode shapes and damping ratios of the free-free line (openTorsion
    ``undamped_modal_analysis`` and ``modal_analysis``)."""
    free = assembly(line, time_domain=False)
    lam, vectors = free.undamped_modal_analysis()
    lam = np.real(lam)
    order = np.argsort(lam)[1:]  # the smallest eigenvalue is the rigid-body mode (ω = 0)
    frequency = np.sqrt(np.maximum(lam[order], 0.0)) / (2.0 * math.pi)
    shapes = np.real(vectors[:, order]).T
    peak = shapes[np.arange(shapes.shape[0]), np.argmax(np.abs(shapes), axis=1)]
    shapes = shapes / peak[:, None]
    wn, _, zeta = free.modal_analysis()
    wn, zeta = np.asarray(wn), np.asarray(zeta)
    flexible = wn > 1e-6 * max(wn.max(), 1.0)
    wn_f, zeta_f = wn[flexible][::2], zeta[flexible][::2]  # complex-conjugate pairs, sorted by |λ|
    nearest = np.abs(wn_f[None, :] - 2.0 * math.pi * frequency[:, None]).argmin(axis=1)
    damping = zeta_f[nearest]
    return Modes(frequency, shapes, damping)
