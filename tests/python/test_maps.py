"""brdfbake.read_map: pixels without a copy laid out as docs/conventions.md says, lookups equal to
`brdfbake sample`'s, every kind of output, and bad input raising brdfbake.Error."""

import json

import numpy as np
import pytest

import brdfbake
from conftest import PHONG_EYE, run_cli


@pytest.fixture(scope="module")
def maps(tmp_path_factory):
    """A sphere, paraboloid, cube and lat-long map of a Phong lobe lit from (1, 1, 1), and a profile."""
    folder = tmp_path_factory.mktemp("maps")
    lit = dict(PHONG_EYE, resolution=64, lights=[{"direction": [1, 1, 1], "color": [1, 0.5, 0.25]}])
    spec = {
        "maps": [dict(lit, output=f"{kind}.exr", parameterization=kind) for kind in ("sphere", "paraboloid", "cube", "latlong")]
        + [dict(PHONG_EYE, output="profile.exr", parameterization="profile", resolution=128, samples_per_texel=4)]
    }
    brdfbake.bake(spec, out_dir=folder, progress=False)
    return folder


def sphere_texel_direction(i, j, n):
    """The direction at texel (i, j)'s centre of an N x N sphere map (docs/conventions.md): s = (i + 0.5)/N,
    t = 1 - (j + 0.5)/N (row 0 at the top), normal (2s - 1, 2t - 1, sqrt(1 - x^2 - y^2)), r = 2 n_z n - z."""
    x, y = 2 * (i + 0.5) / n - 1, 2 * (1 - (j + 0.5) / n) - 1
    normal = np.array([x, y, np.sqrt(1 - x * x - y * y)])
    return 2 * normal[2] * normal - np.array([0.0, 0.0, 1.0])


def test_pixels_are_a_read_only_view_laid_out_as_the_conventions_say(maps):
    m = brdfbake.read_map(maps / "sphere.exr")
    pixels = m.pixels
    assert pixels.shape == (64, 64, 4) and pixels.dtype == np.float32
    assert not pixels.flags.owndata and not pixels.flags.writeable and pixels.base is m
    assert np.shares_memory(pixels, m.pixels)  # no copy on each access either
    with pytest.raises(ValueError):
        pixels[0, 0, 0] = 1
    # A lookup at a texel's centre reads that texel alone: row j, column i as the conventions place it.
    for i, j in [(32, 10), (5, 30), (50, 52), (40, 20)]:
        value = m.sample(sphere_texel_direction(i, j, 64))
        assert np.allclose(value, pixels[j, i], rtol=0, atol=1e-6)
    del m  # the array keeps the map alive
    assert float(pixels.sum()) > 0


def latlong_texel_direction(i, j, n):
    """The direction at texel (i, j)'s centre of a 2N x N lat-long map (docs/conventions.md): u = (i + 0.5)/2N,
    v = (j + 0.5)/N, phi = 2 pi (u - 1/2), theta = pi v; y = cos theta, phi = atan2(x, -z)."""
    phi, theta = 2 * np.pi * ((i + 0.5) / (2 * n) - 0.5), np.pi * (j + 0.5) / n
    return np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], axis=-1)


@pytest.mark.parametrize("name", ["sphere", "latlong"])
def test_pixels_equal_what_the_tool_reads_from_the_file_at_texel_centres(maps, cli, tmp_path, name):
    # The tool reads the file in a process of its own (readMap); a bilinear lookup at a texel's centre
    # returns that texel alone, so its values are the file's texels, to compare with the numpy view.
    pixels = brdfbake.read_map(maps / f"{name}.exr").pixels
    rng = np.random.default_rng(2)
    if name == "sphere":
        texels = [(i, j) for i, j in rng.integers(0, 64, size=(400, 2)) if np.hypot(2 * (i + 0.5) / 64 - 1, 2 * (j + 0.5) / 64 - 1) < 0.95]
        dirs = np.array([sphere_texel_direction(i, j, 64) for i, j in texels])
    else:
        texels = [tuple(t) for t in np.column_stack([rng.integers(0, 128, 400), rng.integers(0, 64, 400)])]
        dirs = np.array([latlong_texel_direction(i, j, 64) for i, j in texels])
    np.savetxt(tmp_path / "dirs.txt", dirs, fmt="%.17g")
    tool = np.array([row["value"] for row in run_cli(cli, "sample", maps / f"{name}.exr", "--dirs", tmp_path / "dirs.txt")])
    ours = np.array([pixels[j, i] for i, j in texels])
    assert len(texels) > 200 and np.max(ours[:, :3]) > 0.1  # the lobe is among them
    assert np.max(np.abs(ours - tool)) <= 1e-6


@pytest.mark.parametrize("name", ["sphere", "paraboloid", "cube", "latlong", "profile"])
def test_lookups_equal_the_tools_for_every_kind(maps, cli, tmp_path, name):
    rng = np.random.default_rng(3)
    dirs = rng.normal(size=(500, 3))
    dirs[0] = [0, 0, -1]  # the sphere map's rim point and a cube corner direction
    dirs[1] = [1, 1, 1]
    np.savetxt(tmp_path / "dirs.txt", dirs, fmt="%.17g")
    tool = run_cli(cli, "sample", maps / f"{name}.exr", "--dirs", tmp_path / "dirs.txt")
    ours = brdfbake.read_map(maps / f"{name}.exr").sample(dirs)
    assert ours.shape == (500, 4) and ours.dtype == np.float64
    assert np.max(np.abs(ours - np.array([row["value"] for row in tool]))) <= 1e-6


def test_a_million_lookups_give_the_tools_values_on_a_subset(maps, cli, tmp_path):
    rng = np.random.default_rng(11)
    dirs = rng.normal(size=(1_000_000, 3))
    values = brdfbake.read_map(maps / "paraboloid.exr").sample(dirs)
    pick = rng.choice(len(dirs), 300, replace=False)
    np.savetxt(tmp_path / "dirs.txt", dirs[pick], fmt="%.17g")
    tool = run_cli(cli, "sample", maps / "paraboloid.exr", "--dirs", tmp_path / "dirs.txt")
    assert np.max(np.abs(values[pick] - np.array([row["value"] for row in tool]))) <= 1e-6


def test_what_a_map_says_about_itself(maps, cli):
    m = brdfbake.read_map(maps / "cube.exr")
    assert (m.kind, m.parameterization, m.resolution) == ("map", "cube", 64)
    assert m.pixels.shape == (3 * 64, 4 * 64, 4)
    info = run_cli(cli, "info", maps / "cube.exr")
    assert m.metadata == info["metadata"]
    assert m.metadata["spec"]["material"]["exponent"] == 50
    assert m.files == [maps / "cube.exr"] and not m.indexed_by_normal and not m.eye_space
    assert m.describe()["kind"] == "map"
    assert "cube" in repr(m)
    profile = brdfbake.read_map(maps / "profile.exr")
    assert (profile.kind, profile.parameterization, profile.resolution) == ("radial_profile", "profile", 128)
    assert profile.pixels.shape == (1, 128, 4) and profile.eye_space


def test_shapes_of_directions(maps):
    m = brdfbake.read_map(maps / "sphere.exr")
    assert m.sample([0, 0, 1]).shape == (4,)
    assert m.sample([[0, 0, 1], [0, 1, 0]]).shape == (2, 4)
    assert m.sample(np.zeros((0, 3))).shape == (0, 4)
    assert np.array_equal(m.sample(np.array([[0, 0, 2]], dtype=np.float32)), m.sample([[0, 0, 1]]))


@pytest.mark.parametrize(
    "dirs, words",
    [
        (np.ones((4, 2)), r"dirs: expected an \(N, 3\) array of directions, got shape \(4, 2\)"),
        (np.ones((2, 3, 3)), r"got shape \(2, 3, 3\)"),
        ([[0, 0, 1], [0, 0, 0]], r"dirs\[1\]: a direction must be finite and non-zero"),
        ([[0, 0, 1], [np.nan, 0, 1]], r"dirs\[1\]: a direction must be finite"),
        ([[0, 0, 1], [np.inf, 0, 1]], r"dirs\[1\]: a direction must be finite"),
        ([["a", "b", "c"]], r"dirs: expected an \(N, 3\) array of directions \(numbers\)"),
        (None, r"dirs: a map is looked up at directions"),
    ],
)
def test_bad_directions_raise_errors_naming_the_row(maps, dirs, words):
    with pytest.raises(brdfbake.InvalidArgumentError, match=words):
        brdfbake.read_map(maps / "sphere.exr").sample(dirs)


def test_cos_view_is_refused_where_it_does_not_apply(maps):
    with pytest.raises(brdfbake.InvalidArgumentError, match="cos_view"):
        brdfbake.read_map(maps / "sphere.exr").sample([0, 0, 1], cos_view=0.5)


def test_files_that_are_no_output_raise_errors_naming_them(tmp_path, source_dir):
    with pytest.raises(brdfbake.IoError, match="nowhere.exr: no such file"):
        brdfbake.read_map(tmp_path / "nowhere.exr")
    (tmp_path / "text.exr").write_text("not an image")
    with pytest.raises(brdfbake.Error, match="text.exr"):
        brdfbake.read_map(tmp_path / "text.exr")
    (tmp_path / "sh.json").write_text(json.dumps({"coefficients": "no"}))
    with pytest.raises(brdfbake.InvalidInputError, match="sh.json"):
        brdfbake.read_map(tmp_path / "sh.json")
    plain = source_dir / "data_samples" / "environments" / "sky_latlong.exr"
    with pytest.raises(brdfbake.InvalidInputError, match="from_"):
        brdfbake.read_map(plain)
    with pytest.raises(brdfbake.InvalidArgumentError, match="from_: "):
        brdfbake.read_map(plain, from_="mercator")
    sky = brdfbake.read_map(plain, from_="latlong")
    assert sky.parameterization == "latlong" and sky.pixels.shape[1] == 2 * sky.pixels.shape[0]
    with pytest.raises(brdfbake.Error, match="mip"):
        brdfbake.read_map(plain, from_="latlong", mip_level=-1)
