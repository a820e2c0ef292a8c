"""brdfbake.prefilter: environments from files and numpy arrays, against the tool's map for the same
input and against the furnace (a constant environment filtered by a normalised lobe is unchanged);
bad input raises brdfbake.Error naming the keyword, and nothing is left behind."""

import math
import tempfile
import pathlib

import numpy as np
import pytest

import brdfbake
from conftest import run_cli, without_keys


@pytest.fixture()
def scratch(tmp_path, monkeypatch):
    """A temporary folder of this test's own for the module's temporaries, to see that none stay."""
    folder = tmp_path / "tmp"
    folder.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    return folder


@pytest.fixture(scope="module")
def sky(source_dir):
    return source_dir / "data_samples" / "environments" / "sky_latlong.exr"


def random_directions(count, seed=1):
    d = np.random.default_rng(seed).normal(size=(count, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


@pytest.mark.parametrize("lobe, to, value", [("phong:20", "paraboloid", 1.0), ("ggx:0.5", "cube", 1.0),
                                             ("mirror", "latlong", 1.0), ("irradiance", "cube", 1.0)])
def test_a_white_furnace_comes_out_as_the_lobes_integral(scratch, lobe, to, value):
    # Radiance 1 everywhere: a normalised lobe (phong, ggx, mirror) integrates to 1, and an
    # irradiance map holds E/pi (docs/conventions.md), 1. The map holds float32 texels, and each method sums over the sphere in
    # double: 1e-5 of the value bounds float32 rounding of the sums' terms, far inside the 1 % bound
    # the map is made to.
    environment = np.ones((32, 64, 3), dtype=np.float32)
    m = brdfbake.prefilter(environment, lobe, to, 16, progress=False)
    values = m.sample(random_directions(2000))
    assert np.max(np.abs(values[:, :3] - value)) < 1e-5 * value
    assert m.result["prefilter"]["method"] and m.result["environment"]["lobe"] == lobe
    assert list(scratch.iterdir()) == []


def test_a_prefiltered_file_is_the_tools_map(sky, cli, tmp_path, scratch):
    tool = run_cli(cli, "prefilter", sky, "--lobe", "phong:20", "--to", "sphere", "--resolution", 32,
                   "-o", tmp_path / "tool.exr")
    ours = brdfbake.prefilter(sky, "phong:20", "sphere", 32, output=tmp_path / "module.exr", progress=False)
    assert ours.path == tmp_path / "module.exr" and (tmp_path / "module.exr").exists()
    assert np.array_equal(ours.pixels, brdfbake.read_map(tmp_path / "tool.exr").pixels)
    skip = {"seconds", "bake_seconds", "estimate_seconds"}
    # The map's summary in memory is the tool's entry but for what the tool adds about its files.
    assert set(tool) - set(ours.result) == {"output", "status", "files", "write_seconds", "notes"}
    assert without_keys(ours.result, skip) == without_keys({k: tool[k] for k in ours.result}, skip)
    assert ours.files == [tmp_path / "module.exr"]
    dirs = random_directions(300, seed=4)
    np.savetxt(tmp_path / "dirs.txt", dirs, fmt="%.17g")
    sampled = run_cli(cli, "sample", tmp_path / "tool.exr", "--dirs", tmp_path / "dirs.txt")
    assert np.max(np.abs(ours.sample(dirs) - np.array([row["value"] for row in sampled]))) <= 1e-6
    assert list(scratch.iterdir()) == []


def test_an_array_prefilters_as_the_file_it_came_from(sky, tmp_path, scratch):
    radiance = brdfbake.read_map(sky, from_="latlong").pixels[:, :, :3]
    from_array = brdfbake.prefilter(radiance, "blinn:40", "paraboloid", 16, progress=False)
    from_file = brdfbake.prefilter(sky, "blinn:40", "paraboloid", 16, progress=False)
    assert np.array_equal(from_array.pixels, from_file.pixels)
    assert from_array.result["environment"]["parameterization"] == "latlong"
    assert list(scratch.iterdir()) == []


def test_mips_stay_in_memory_until_saved(sky, tmp_path, scratch):
    m = brdfbake.prefilter(sky, "phong:20", "paraboloid", 16, mips=True, progress=False)
    assert m.path is None and m.files == []
    levels = m.levels
    assert [level.shape for level in levels] == [(16 >> k, 2 * (16 >> k), 4) for k in range(5)]
    assert np.array_equal(levels[0], m.pixels)
    # The solid-angle mip chain: a level's texel is the solid-angle-weighted mean of the four below it
    # (texels of the paraboloid's hemispheres of their own sizes; interior texels of full coverage).
    written = m.save(tmp_path / "sky.exr")
    assert written == [tmp_path / f"sky{'' if k == 0 else f'_mip{k}'}.exr" for k in range(5)]
    for k in range(5):
        assert np.array_equal(brdfbake.read_map(tmp_path / "sky.exr", mip_level=k).pixels, levels[k])
    assert list(scratch.iterdir()) == []


def test_several_maps_need_an_output(source_dir, tmp_path, scratch):
    with pytest.raises(brdfbake.InvalidArgumentError, match="output: a Fresnel decomposition"):
        brdfbake.prefilter(source_dir / "data_samples/environments/sky_latlong.exr", "phong:20", "cube", 8,
                           fresnel_ior=1.5, progress=False)
    m = brdfbake.prefilter(source_dir / "data_samples/environments/sky_latlong.exr", "phong:20", "cube", 8,
                           fresnel_ior=1.5, output=tmp_path / "f.exr", progress=False)
    assert (tmp_path / "f_irradiance.exr").exists() and (tmp_path / "f_fresnel.exr").exists()
    assert m.path == tmp_path / "f.exr"
    # A lobe varying with the view: one map per elevation, so files, never a result whose files are gone.
    varying = "lobes:" + str(source_dir / "data_samples/fits/synthetic_varying.json")
    with pytest.raises(brdfbake.InvalidArgumentError, match="output: .*elevation stack"):
        brdfbake.prefilter(source_dir / "data_samples/environments/sky_latlong.exr", varying, "sphere", 8,
                           progress=False)
    stack = brdfbake.prefilter(source_dir / "data_samples/environments/sky_latlong.exr", varying, "sphere", 8,
                               elevations=3, output=tmp_path / "v.exr", progress=False)
    assert all(pathlib.Path(f).exists() for f in stack.files) and len(stack.files) >= 3
    assert stack.pixels.shape == (3, 8, 8, 4)  # one 8 x 8 sphere map per elevation


def test_a_nul_in_an_output_path_is_refused_before_any_work(sky, tmp_path, scratch):
    with pytest.raises(brdfbake.InvalidArgumentError, match="contains a NUL character"):
        brdfbake.prefilter(sky, "phong:20", "sphere", 8, output=str(tmp_path / "x.exr") + "\0.exr", progress=False)
    assert list(tmp_path.glob("x*")) == [] and list(scratch.iterdir()) == []


@pytest.mark.parametrize(
    "environment, words",
    [
        (np.ones((10, 10)), r"environment: expected an \(H, 2H, 3\) array"),
        (np.ones((4, 8, 2)), r"got shape \(4, 8, 2\)"),
        ("nan", r"environment\[1, 2, 0\]: radiance must be finite"),
        ([["a"]], r"environment: expected an \(H, 2H, 3\) array"),
    ],
)
def test_bad_arrays_raise_errors_naming_the_element(environment, words, scratch):
    if isinstance(environment, str):
        environment = np.ones((8, 16, 3), dtype=np.float32)
        environment[1, 2, 0] = np.nan
    with pytest.raises(brdfbake.InvalidArgumentError, match=words):
        brdfbake.prefilter(environment, "phong:20", "sphere", 8, progress=False)
    assert list(scratch.iterdir()) == []


@pytest.mark.parametrize(
    "arguments, words",
    [
        ({"lobe": "bogus"}, "lobe: "),
        ({"to": "mercator"}, "to: "),
        ({"resolution": 0}, "resolution: "),
        ({"method": "magic"}, "method: "),
        ({"max_error": 0.7}, "max_error: "),
        ({"fresnel_ior": 1.5, "lobe": "irradiance"}, "fresnel_ior: "),
    ],
)
def test_bad_arguments_raise_errors_naming_the_keyword(sky, tmp_path, scratch, arguments, words):
    call = dict(lobe="phong:20", to="sphere", resolution=8, output=tmp_path / "out.exr", progress=False) | arguments
    with pytest.raises(brdfbake.Error) as caught:
        brdfbake.prefilter(sky, **call)
    assert words in str(caught.value) and "maps[0]" not in str(caught.value)
    assert list(tmp_path.glob("out*")) == [] and list(scratch.iterdir()) == []


def test_an_array_with_a_bad_lobe_names_the_array_not_a_temporary(scratch):
    with pytest.raises(brdfbake.Error) as caught:
        brdfbake.prefilter(np.ones((8, 4, 3), dtype=np.float32), "phong:20", "sphere", 8, progress=False)
    assert "environment array" in str(caught.value) and str(scratch) not in str(caught.value)
    assert list(scratch.iterdir()) == []


def test_a_missing_environment_raises_an_io_error_naming_it(tmp_path, scratch):
    with pytest.raises(brdfbake.IoError, match="nowhere.exr"):
        brdfbake.prefilter(tmp_path / "nowhere.exr", "phong:20", "sphere", 8, progress=False)
    assert list(scratch.iterdir()) == []


def test_a_lambertian_surface_in_the_furnace_file_reflects_its_albedo(source_dir, scratch):
    # data_samples' furnace is radiance 1 everywhere (checked here): the irradiance E is pi at every
    # normal, the map holds E/pi, and a Lambertian surface of albedo a reflects a E/pi, a itself.
    furnace = source_dir / "data_samples" / "environments" / "furnace_latlong.exr"
    assert np.all(brdfbake.read_map(furnace, from_="latlong").pixels[:, :, :3] == 1.0)
    irradiance = brdfbake.prefilter(furnace, "irradiance", "cube", 8, progress=False)
    albedo = np.array([0.2, 0.5, 0.8])
    reflected = albedo * irradiance.sample(random_directions(1000, seed=9))[:, :3]
    assert np.allclose(reflected, albedo, rtol=1e-6, atol=0)
    assert list(scratch.iterdir()) == []


def test_fitted_lobes_in_the_furnace_give_their_integral(source_dir, tmp_path, scratch):
    # A fitted channel's lobes sum_k C_k (n_k + 2)/(2 pi) max(0, r.l)^n_k integrate over the sphere to
    # sum_k C_k (n_k + 2)/(n_k + 1) (docs/prefilter.md), the value a white furnace gives at every r.
    fit = brdfbake.fit(source_dir / "data_samples" / "tables" / "synthetic_two_lobes.astm", kind="mirror",
                       held_out=False, progress=False)
    fit.save(tmp_path / "fit.json")
    m = brdfbake.prefilter(np.ones((32, 64, 3), dtype=np.float32), f"lobes:{tmp_path / 'fit.json'}", "paraboloid", 16,
                           progress=False)
    integrals = [sum(lobe["weight"][0] * (lobe["exponent"][0] + 2) / (lobe["exponent"][0] + 1) for lobe in lobes)
                 for lobes in fit.lobes]
    values = m.sample(random_directions(1000, seed=3))[:, :3]
    assert np.allclose(values, integrals, rtol=1e-5, atol=0)
    assert list(scratch.iterdir()) == []
