"""The blade milling model against the thesis' FEM cusps and the IACS UR I3 Q_max (docs/propeller.md, "Blade
milling model").

Usage:  python scripts/milling_comparison.py

Agulhas II propeller (PropellerSpec defaults: D 4.3 m, Z 4, hub 0.30, EAR 0.55, t_0.7 0.105 m), 140 rpm,
advance speed 3 m/s (thesis Eq. 28), the model's default parameters. Prints two markdown tables: the four FEM
cusps of thesis Tables 10/11 (block = the cusp's box: thickness = height, length along the axis = its length,
width = its width) at 0 % and 95.8551 % pitch; and a block of the class' H_ice (H_ice × 2H_ice × 3H_ice:
thickness H_ice, width 2H_ice, length 3H_ice along the axis) at 95.8551 % pitch against ur_i3_loads' Q_max.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from floebreak.app.inputs import shipped_fem_tables
from floebreak.propeller.iceclass import POLAR_CLASSES, ur_i3_loads
from floebreak.propeller.loads.milling import BladeGeometry, IceBlock, impact_loads
from floebreak.propeller.spec import PropellerSpec

RPM = 140.0
ADVANCE_SPEED_M_S = 3.0


def fem_rows(spec: PropellerSpec) -> list[str]:
    lines = [
        "| pitch | cusp V [m³] | l × w × h [m] | Q model [kN·m] | Q FEM [kN·m] | model/FEM | "
        "F model [kN] | F FEM [kN] | model/FEM | removed | impacts |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for table_pitch, table in sorted(shipped_fem_tables().items()):
        pitch = 0.0 if table_pitch == 0.0 else spec.pitch_percent
        blade = BladeGeometry.from_spec(replace(spec, pitch_percent=pitch))
        block = IceBlock(table.height_m, table.length_m, table.width_m)
        loads = impact_loads(block, blade, RPM, ADVANCE_SPEED_M_S)
        for i in range(table.volume_m3.size):
            q_fem, f_fem = abs(table.torque_nm[i]) / 1e3, abs(table.force_n[i]) / 1e3
            q, f = loads.torque_n_m[i] / 1e3, loads.force_n[i] / 1e3
            box = f"{table.length_m[i]:.2f} × {table.width_m[i]:.2f} × {table.height_m[i]:.2f}"
            cells = (
                f"{pitch:g} %",
                f"{table.volume_m3[i]:.2f}",
                box,
                f"{q:.0f}",
                f"{q_fem:.0f}",
                f"{q / q_fem:.2f}",
                f"{f:.0f}",
                f"{f_fem:.0f}",
                f"{f / f_fem:.2f}",
                f"{loads.removed_fraction[i]:.2f}",
                f"{loads.n_impacts[i]}",
            )
            lines.append("| " + " | ".join(cells) + " |")
    return lines


def rule_rows(spec: PropellerSpec) -> list[str]:
    lines = [
        "| class | H_ice [m] | Q model [kN·m] | Q_max rule [kN·m] | model/rule | F model [kN] | "
        "F_b rule [kN] | F_f rule [kN] | impacts |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    blade = BladeGeometry.from_spec(spec)
    for name in ("PC5", "PC7"):
        h_ice = POLAR_CLASSES[name][0]
        loads = impact_loads(IceBlock(np.array([h_ice]), 3 * h_ice, 2 * h_ice), blade, RPM, ADVANCE_SPEED_M_S)
        rule = ur_i3_loads(spec, name)
        q = loads.torque_n_m[0] / 1e3
        lines.append(
            f"| {name} | {h_ice:g} | {q:.0f} | {rule.max_torque_nm / 1e3:.0f} | "
            f"{q * 1e3 / rule.max_torque_nm:.2f} | {loads.force_n[0] / 1e3:.0f} | "
            f"{rule.backward_force_n / 1e3:.0f} | {rule.forward_force_n / 1e3:.0f} | {loads.n_impacts[0]} |"
        )
    return lines


def main() -> None:
    spec = PropellerSpec()
    print("\n".join(fem_rows(spec)))
    print()
    print("\n".join(rule_rows(spec)))


if __name__ == "__main__":
    main()
