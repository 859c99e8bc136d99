"""The figures of docs/gallery.md that ``bemcontact run`` draws: each
example problem file solved as the command solves it (ProblemFile.solve and
.write, the same files) and its figures copied into docs/figures/.

    .venv/bin/python docs/figures/make_gallery_figures.py [--out DIR] [--only NAME]

* ``gallery_two_cubes_frame.png``: frame_tractions.png of
  examples/two_cubes_dissimilar.toml (about 2 s).
* ``gallery_block_frame.png``: frame_tractions.png of
  examples/block_from_mesh_file.toml (about 5 s).
* ``gallery_hertz_frame.png``, ``gallery_hertz_profile.png``,
  ``gallery_hertz_stresses.png``: frame_tractions.png, frame_profile.png and
  the block's stresses_block.png of examples/hertz_sphere_on_block.toml
  (needs gmsh; about 30 s).
* ``gallery_bearing_profile.png``: the upper pair's
  ``ball+upper_frame_profile.png`` of examples/thrust_bearing_ball.toml, an
  assembly (needs gmsh; about 40 s).
* ``gallery_multiscale_grid.png``, ``gallery_rolling_grid.png``,
  ``gallery_two_indenters_grid.png``: grid_tractions.png of
  examples/cattaneo_mindlin_multiscale.toml and rolling_ball_multiscale.toml,
  and the right pair's ``block+right_grid_tractions.png`` of
  two_indenters_multiscale.toml, on the contact grid (needs gmsh; about 5 s
  each).

The other gallery figures are docs/validation.md's
(``make_validation_figures.py``).
"""

from __future__ import annotations

import argparse
import pathlib
import shutil
import sys
import tempfile

import bemcontact as bc

ROOT = pathlib.Path(__file__).resolve().parents[2]
FIGURES = pathlib.Path(__file__).resolve().parent

#: name -> (problem file, {figure written by the run: gallery file name})
GALLERY = {
    "two_cubes": ("two_cubes_dissimilar.toml",
                  {"frame_tractions.png": "gallery_two_cubes_frame.png"}),
    "block": ("block_from_mesh_file.toml", {"frame_tractions.png": "gallery_block_frame.png"}),
    "hertz": ("hertz_sphere_on_block.toml", {"frame_tractions.png": "gallery_hertz_frame.png",
                                             "frame_profile.png": "gallery_hertz_profile.png",
                                             "stresses_block.png": "gallery_hertz_stresses.png"}),
    "bearing": ("thrust_bearing_ball.toml",
                {"ball+upper_frame_profile.png": "gallery_bearing_profile.png"}),
    "multiscale": ("cattaneo_mindlin_multiscale.toml",
                   {"grid_tractions.png": "gallery_multiscale_grid.png"}),
    "rolling": ("rolling_ball_multiscale.toml", {"grid_tractions.png": "gallery_rolling_grid.png"}),
    "two_indenters": ("two_indenters_multiscale.toml",
                      {"block+right_grid_tractions.png": "gallery_two_indenters_grid.png"}),
}


def make(name: str, out: pathlib.Path) -> list[pathlib.Path]:
    toml, figures = GALLERY[name]
    problem = bc.load_problem(ROOT / "examples" / toml)
    result = problem.solve()
    with tempfile.TemporaryDirectory() as tmp:
        problem.write(result, pathlib.Path(tmp) / "run")
        made = []
        for src, dst in figures.items():
            made.append(pathlib.Path(shutil.copy(pathlib.Path(tmp) / "run" / src, out / dst)))
    if hasattr(result, "frame"):  # the full path
        forces = ", ".join(f"{p.normal_force:.6g}" for p in result.pairs or [result])
        where = f"frame {result.frame.counts()}"
    else:  # the contact grid (an assembly: a grid per pair)
        grids = getattr(result, "pairs", None) or [result]
        forces = ", ".join(f"{g.history[-1].force[2]:.6g}" for g in grids)
        where = "the contact grid"
    print(f"{toml}: normal force(s) {forces}, {where}; " + ", ".join(p.name for p in made))
    return made


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=pathlib.Path, default=FIGURES)
    ap.add_argument("--only", action="append", choices=sorted(GALLERY))
    args = ap.parse_args(argv)
    for name in args.only or GALLERY:
        make(name, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
