"""Figures (plot.py): radial profiles and force-displacement curves are
written atomically as PNG; bad arguments give one-line errors."""

from __future__ import annotations

import numpy as np
import pytest

import bemcontact as bc
from bemcontact.output.plot import plot_force_displacement, plot_radial_profile

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def result():
    lower = bc.ElasticBody(
        bc.box((0, 0, 0), (2, 2, 2), 2), bc.LinearElastic(1e4, 0.3), {"zmin": bc.Fixed()},
        name="lower",
    )
    upper = bc.ElasticBody(
        bc.box((0.5, 0.5, 2), (1.5, 1.5, 3), 1), bc.LinearElastic(1e4, 0.3),
        {"zmax": bc.Displacement((0.001, 0, -0.02))}, name="upper",
    )
    return bc.ContactProblem(lower, upper, bc.ContactPair("zmax", "zmin", 0.2)).solve(
        bc.SolverOptions(threads=1)
    )


def test_radial_profile_png(result, tmp_path):
    calls = []

    def exact(r):
        calls.append(r)
        return np.full_like(r, 50.0)

    out = plot_radial_profile(result, tmp_path / "p.png", pressure=exact, traction=exact,
                              center=(1.0, 1.0), title="t")
    assert out == tmp_path / "p.png"
    assert out.read_bytes()[:8] == PNG
    assert [p.name for p in tmp_path.iterdir()] == ["p.png"]  # no temporary left
    assert len(calls) == 2 and calls[0].min() == 0.0 and calls[0].max() > 0.5
    # a FrameResult works too
    assert plot_radial_profile(result.frame, tmp_path / "q.png").read_bytes()[:8] == PNG


def test_force_displacement_png(tmp_path):
    u = np.array([0.0, 1.0, 0.5, -1.0, 0.0])
    f = np.array([0.0, 2.0, 1.0, -2.0, 0.0])
    out = plot_force_displacement(u, f, tmp_path / "loop.png", analytic=(u, f), title="loop")
    assert out.read_bytes()[:8] == PNG


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda r, d: plot_radial_profile("x", d / "a.png"), "expected a ContactResult or FrameResult, got str"),
        (lambda r, d: plot_radial_profile(r, d / "a.png", component=2), "component must be 0 or 1"),
        (lambda r, d: plot_radial_profile(r, d / "missing" / "a.png"), "does not exist"),
        (lambda r, d: plot_force_displacement([0, 1], [0], d / "a.png"), "got 2 and 1"),
    ],
)
def test_bad_arguments(result, tmp_path, call, message):
    with pytest.raises(bc.ConfigError, match=message):
        call(result, tmp_path)
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------ frame maps and profiles

from bemcontact.contact.law import SLIP, STICK  # noqa: E402
from bemcontact.output import plot  # noqa: E402
from bemcontact.output.vtu import frame_cells  # noqa: E402
from bemcontact.validation import cases  # noqa: E402

#: A coarse sphere on a block (h = 0.15 mm, a ≈ 0.55 mm on a 20 x 20 mm face).
COARSE = cases.SphereOnBlock(fine_radius=0.9, coarse_size=5.0, growth=0.5)


@pytest.fixture(scope="module")
def sphere():
    """Cattaneo–Mindlin: pressed 0.03 mm, then Q = 0.5 mu P (stick and slip)."""
    steps = [bc.LoadStep(label="P")] + cases.tangential_steps([0.5 * 0.3 * 2600], 0.03,
                                                              increments=1)
    return cases.sphere_on_block(0.15, 0.03, friction_coefficient=0.3, setup=COARSE).solve(
        bc.SolverOptions(threads=1), steps=steps)


@pytest.fixture(scope="module")
def frictionless():
    return cases.sphere_on_block(0.15, 0.03, setup=COARSE).solve(bc.SolverOptions(threads=1))


def _pixels(fig):
    """(RGB image (h, w, 3) floats in [0, 1], pixel boxes of the axes)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    img = np.asarray(canvas.buffer_rgba())[..., :3] / 255.0
    h = img.shape[0]
    boxes = []
    for ax in fig.axes:
        b = ax.get_window_extent()
        boxes.append((int(h - b.y1) + 2, int(h - b.y0) - 2, int(b.x0) + 2, int(b.x1) - 2))
    return img, boxes


def _contact_radius(result):
    xy = result.frame.points[:, :2]
    return float(np.hypot(*xy[result.frame.state > 0].T).max())


def test_frame_tractions_zoomed_to_the_contact_zone_with_units_and_outlines(sphere, tmp_path):
    """The 20 x 20 mm face holds a contact of radius 0.55 mm: the maps show
    the closed nodes plus a quarter of their extent on each side, so the
    contact (pressure > 0, colours other than the colour of 0) covers about
    half of each map, not 0.3 % of it; every pixel's colour is on the
    colour map (flat shading) but for the two outlines."""
    from matplotlib.colors import to_rgb
    from matplotlib.collections import TriMesh

    fig = plot.frame_tractions_figure(sphere, cells=frame_cells(sphere), length_unit="mm",
                                      stress_unit="MPa", force_unit="N")
    maps = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title() for ax in maps] == ["contact pressure", "tangential traction"]
    assert [ax.get_xlabel() for ax in maps] == ["x (mm)"] * 2
    assert [ax.get_ylabel() for ax in fig.axes] == ["y (mm)", "y (mm)", "p (MPa)", "|q| (MPa)"]
    assert "normal force 2" in fig.get_suptitle() and fig.get_suptitle().endswith(" N")
    assert not any(isinstance(c, TriMesh) for ax in maps for c in ax.collections)  # no Gouraud
    a = _contact_radius(sphere)
    assert 0.45 < a < 0.6
    for ax in maps:
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        assert 2.0 * a < x1 - x0 < 3.2 * a and 2.0 * a < y1 - y0 < 3.2 * a, (x0, x1, a)
    img, boxes = _pixels(fig)
    assert img.shape == (690, 1560, 3)  # 10.4 x 4.6 in at 150 dpi
    r0, r1, c0, c1 = boxes[0]
    area = img[r0:r1, c0:c1].reshape(-1, 3)
    import matplotlib

    lut = matplotlib.colormaps["viridis"](np.linspace(0, 1, 256))[:, :3]
    zero = np.linalg.norm(area - lut[0], axis=1) < 0.08
    contact = 1.0 - zero.mean()
    assert 0.35 < contact < 0.8, contact
    white = (area > 0.95).all(axis=1).mean()
    red = (np.linalg.norm(area - to_rgb(plot.STICK_EDGE["colors"]), axis=1) < 0.15).mean()
    assert white > 0.005 and red > 0.002, (white, red)
    some = area[::7]
    off = np.min(np.linalg.norm(some[:, None, :] - lut[None, ::4], axis=2), axis=1) > 0.1
    assert off.mean() < white + 2 * red + 0.02, (off.mean(), white, red)
    out = plot.plot_frame_tractions(sphere, tmp_path / "f.png", cells=frame_cells(sphere))
    from PIL import Image

    with Image.open(out) as im:
        assert im.size == (1560, 690)


def test_frictionless_frame_map_has_no_flat_zero_panel(frictionless, tmp_path):
    fig = plot.frame_tractions_figure(frictionless, cells=frame_cells(frictionless))
    assert [ax.get_title() for ax in fig.axes if ax.get_title()] == ["contact pressure"]
    assert "tangential force 0" in fig.get_suptitle()
    img, _ = _pixels(fig)
    assert img.shape == (690, 780, 3)
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend == [f"contact edge: closed inside ({(frictionless.frame.state > 0).sum()} "
                      f"nodes), open outside ({(frictionless.frame.state == 0).sum()})"]


def test_contact_window_clips_to_the_frame_and_opens_up_without_contact():
    xy = np.array([[0, 0], [10, 0], [0, 10], [10, 10], [5, 5], [5.5, 5]], dtype=float)
    w = np.full(6, 0.01)
    state = np.array([0, 0, 0, 0, STICK, SLIP], dtype=np.int8)
    x0, x1, y0, y1 = plot.contact_window(xy, state, w)
    assert (x0, x1) == pytest.approx((5 - 0.2, 5.5 + 0.2)) and (y0, y1) == pytest.approx((4.8, 5.2))
    assert plot.contact_window(xy, np.zeros(6), w) == (0, 10, 0, 10)
    state[:] = STICK
    assert plot.contact_window(xy, state, w) == (0, 10, 0, 10)


def test_axisymmetry_tells_a_sphere_from_a_square_punch(sphere, frictionless, result):
    for res in (sphere, frictionless):
        centre, scatter = plot.axisymmetry(res.frame)
        assert np.abs(centre).max() < 0.01 and scatter < 0.1, (centre, scatter)
    assert plot.axisymmetry(result.frame) is None  # 4 closed nodes: too few to tell
    square = bc.load_problem("examples/two_cubes_similar.toml").solve(threads=1)
    centre, scatter = plot.axisymmetry(square.frame)
    assert centre == pytest.approx([1.0, 1.0])
    assert scatter > 1.5 * plot.AXISYMMETRIC_SCATTER, scatter


def test_radial_profile_of_pressure_and_shear(sphere, frictionless, tmp_path):
    from PIL import Image

    out = plot.plot_radial_profile(sphere, tmp_path / "r.png", component=None, center=None)
    with Image.open(out) as im:
        assert im.size == (1500, 600)
    out = plot.plot_radial_profile(frictionless, tmp_path / "s.png", component=None, center=None,
                                   length_unit="", stress_unit="")
    with Image.open(out) as im:
        assert im.size == (750, 600)  # no flat |q| panel


def test_written_figures_carry_the_problem_files_units(sphere, tmp_path):
    """write_results draws frame_tractions.png with the problem file's units
    and, the contact being axisymmetric, frame_profile.png."""
    from PIL import Image

    from bemcontact.output import write as io

    echo = {"file": "p.toml", "units": {"length": "mm", "force": "N", "stress": "MPa"}}
    files = io.write_results(sphere, tmp_path / "o", echo,
                             io.OutputOptions(vtu=False, csv=False, figures=True,
                                              default_stresses=False))
    assert [f.name for f in files] == ["summary.json", "frame_tractions.png", "frame_profile.png"]
    with Image.open(files[1]) as a, Image.open(files[2]) as b:
        assert a.size == (1560, 690) and b.size == (1500, 600)
