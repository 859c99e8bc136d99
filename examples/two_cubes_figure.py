"""The founding paper's Figure 1 for the two-cubes example: the lateral
displacement u_y of both cubes' contact-surface nodes along a line in x,
for similar and for dissimilar materials.

Run after solving both problems with the CLI:

    bemcontact run examples/two_cubes_similar.toml --out out/similar
    bemcontact run examples/two_cubes_dissimilar.toml --out out/dissimilar
    python examples/two_cubes_figure.py out/similar out/dissimilar out/two_cubes_figure1.png

The figure is rebuilt from the ``<body>_interface.csv`` files of the two
result directories, along the line y ≈ 0.53 mm (a quarter of the interface
nodes' width from its lower edge; the
meshes do not match, so each body's nodal values are interpolated linearly
onto the line, see :func:`bemcontact.output.plot.interface_line`).  With similar
materials the interface sticks and both cubes share one lateral displacement
field (u_y about proportional to y - 1): the curves coincide.  With the
nearly rigid upper cube, the lower cube expands laterally and slips under the
upper one, whose u_y stays near zero: the curves differ (Figure 1b).
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np

from bemcontact.output.plot import interface_line, plot_interface_line


def run(similar: str, dissimilar: str, png: str) -> dict[str, float]:
    """Write the figure; return the largest |u_y| of each body on the line per
    case (the key numbers of the figure)."""
    dirs = {"similar": similar, "dissimilar": dissimilar}
    plot_interface_line(dirs, png, component=1, axis=0)
    out = {}
    for case, d in dirs.items():
        lines = interface_line(d, axis=0)
        for line in lines:
            out[f"{case}_{line.body}_max_abs_uy"] = float(abs(line.displacement[:, 1]).max())
        # difference of the two curves at the first body's points (common range)
        a, b = lines
        x = a.coordinate[(a.coordinate >= b.coordinate[0]) & (a.coordinate <= b.coordinate[-1])]
        ua = np.interp(x, a.coordinate, a.displacement[:, 1])
        ub = np.interp(x, b.coordinate, b.displacement[:, 1])
        out[f"{case}_max_abs_uy_difference"] = float(np.abs(ua - ub).max())
    return out


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(f"usage: {pathlib.Path(sys.argv[0]).name} SIMILAR_DIR DISSIMILAR_DIR OUT.png")
    values = run(*sys.argv[1:4])
    print(f"wrote {sys.argv[3]}")
    for k, v in values.items():
        print(f"  {k} = {v:.4g} mm")
