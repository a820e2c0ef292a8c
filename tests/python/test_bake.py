"""brdfbake.bake: a spec as a dict or a file, against the tool's output for the same spec and against
the analytic Phong map; bad specs raise brdfbake.Error naming the JSON path and write nothing."""

import json
import math

import numpy as np
import pytest

import brdfbake
from conftest import PHONG_EYE, run_cli, without_keys

TIMINGS = {"bake_seconds", "write_seconds", "seconds"}


def test_a_dict_spec_bakes_what_the_tool_bakes_from_the_same_spec_file(tmp_path, cli):
    # A cube map is indexed by the reflected direction alone: its light is fixed, not at the eye.
    cube = dict(PHONG_EYE, output="phong_cube.exr", parameterization="cube", resolution=32,
                lights=[{"direction": [1, 1, 1], "color": [1, 0.5, 0.25]}])
    spec = {"maps": [PHONG_EYE, cube]}
    (tmp_path / "spec.json").write_text(json.dumps(spec))
    tool = run_cli(cli, "bake", tmp_path / "spec.json", "--out-dir", tmp_path / "tool")
    result = brdfbake.bake(spec, out_dir=tmp_path / "module", progress=False)

    assert isinstance(result, brdfbake.BakeResult)
    assert result.failed == 0 and [m.written for m in result.maps] == [True, True]
    ours = result.to_json()
    assert ours["spec"] == "spec"
    # The same entries, key for key, but for where the files went and how long it took.
    for mine, theirs in zip(ours["maps"], tool["maps"]):
        assert set(mine) == set(theirs)
        mine = without_keys(mine, TIMINGS | {"output", "files"})
        theirs = without_keys(theirs, TIMINGS | {"output", "files"})
        assert mine == theirs
    for name in ("phong_eye.exr", "phong_cube.exr"):
        assert (tmp_path / "module" / name).exists()
        a = brdfbake.read_map(tmp_path / "module" / name).pixels
        b = brdfbake.read_map(tmp_path / "tool" / name).pixels
        assert np.array_equal(a, b)
    assert [p.name for p in result.files] == [f.split("/")[-1] for m in tool["maps"] for f in m["files"]]
    assert result.maps[0].json_path == "maps[0]"
    assert "phong_eye.exr" in result.brief_report()


def test_a_spec_file_bakes_into_out_dir(tmp_path, source_dir):
    result = brdfbake.bake(source_dir / "data_samples" / "specs" / "phong_eye.json", out_dir=tmp_path, progress=False)
    assert result.spec == source_dir / "data_samples" / "specs" / "phong_eye.json"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["phong_eye.exr", "phong_paraboloid.exr"]


def test_a_phong_sphere_map_lit_from_the_eye_holds_max_0_rz_to_the_n(tmp_path):
    # Light at the eye (l = v = +z): the Phong lobe max(0, r.l)^n is max(0, r_z)^n at every map
    # direction r. The baked texel is the lobe's mean over its footprint and the lookup bilinear,
    # which README's accuracy section bounds by 1 % of the peak away from the rim (10 degrees of -z).
    brdfbake.bake({"maps": [PHONG_EYE]}, out_dir=tmp_path, progress=False)
    rng = np.random.default_rng(7)
    dirs = rng.normal(size=(20000, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    dirs = dirs[dirs[:, 2] > -math.cos(math.radians(10))]
    values = brdfbake.read_map(tmp_path / "phong_eye.exr").sample(dirs)
    expected = np.maximum(0.0, dirs[:, 2]) ** 50
    for c in range(3):
        assert np.max(np.abs(values[:, c] - expected)) < 0.01
    # Alpha is the texel's coverage of the disc (docs/conventions.md). Up to 150 degrees from +z the
    # normal is within 75 degrees of the view, at radius sin(75) = 0.966 of the disc: more than four
    # texels (2/256 wide) inside its rim, so a bilinear lookup reads whole texels only.
    inside = dirs[:, 2] > math.cos(math.radians(150))
    assert np.all(values[inside, 3] == 1.0)


def test_a_bad_spec_raises_an_error_naming_the_json_path_and_writes_nothing(tmp_path):
    spec = {"maps": [dict(PHONG_EYE, material={"model": "phong", "specular": [1, 1, 1], "exponent": -3})]}
    with pytest.raises(brdfbake.InvalidInputError) as caught:
        brdfbake.bake(spec, out_dir=tmp_path, progress=False)
    assert "maps[0].material.exponent" in str(caught.value)
    assert caught.value.kind == "invalid_input"
    assert isinstance(caught.value, brdfbake.Error) and isinstance(caught.value, ValueError)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "value, path, words",
    [
        (float("nan"), "maps[0].material.exponent", "finite"),
        (float("inf"), "maps[0].material.exponent", "finite"),
        (object(), "maps[0].material.exponent", "not a JSON value"),
        (10**30, "maps[0].material.exponent", "64 bits"),
    ],
)
def test_values_a_json_spec_cannot_hold_are_refused_naming_their_path(tmp_path, value, path, words):
    spec = {"maps": [dict(PHONG_EYE, material={"model": "phong", "specular": [1, 1, 1], "exponent": value})]}
    with pytest.raises(brdfbake.InvalidInputError) as caught:
        brdfbake.bake(spec, out_dir=tmp_path, progress=False)
    assert f"spec: {path}: " in str(caught.value) and words in str(caught.value)
    assert list(tmp_path.iterdir()) == []


def test_keys_must_be_strings_and_nesting_is_bounded(tmp_path):
    with pytest.raises(brdfbake.InvalidInputError, match=r"spec: maps\[0\]: the key 3 is not a string"):
        brdfbake.bake({"maps": [{3: "x"}]}, out_dir=tmp_path, progress=False)
    deep = []
    for _ in range(100):
        deep = [deep]
    with pytest.raises(brdfbake.InvalidInputError, match="nested deeper than 64 levels"):
        brdfbake.bake({"maps": deep}, out_dir=tmp_path, progress=False)


@pytest.mark.parametrize(
    "spec, path",
    [
        ({"maps": [dict(PHONG_EYE, output="x.exr\0.exr")]}, r"maps\[0\]\.output"),
        ({"maps": [dict(PHONG_EYE, output="pic.png\0.exr")]}, r"maps\[0\]\.output"),
        ({"maps": [dict(PHONG_EYE, **{"out\0put": "x.exr"})]}, r"maps\[0\]"),
    ],
)
def test_a_nul_in_a_dict_spec_is_refused_before_any_work_as_in_json_text(tmp_path, spec, path):
    # The system would cut "x.exr\0.exr" at the NUL and write x.exr while reporting the whole name.
    with pytest.raises(brdfbake.InvalidInputError, match=f"spec: {path}: contains a NUL character"):
        brdfbake.bake(spec, out_dir=tmp_path, progress=False)
    assert list(tmp_path.iterdir()) == []


def test_paths_tuples_and_numpy_values_are_json_values(tmp_path):
    spec = {
        "maps": (
            dict(
                PHONG_EYE,
                output=tmp_path / "phong.exr",
                resolution=np.int64(16),
                material={"model": "phong", "specular": np.ones(3), "exponent": np.float32(50)},
            ),
        )
    }
    result = brdfbake.bake(spec, out_dir=tmp_path, progress=False)
    assert result.maps[0].to_json()["resolution"] == 16
    assert (tmp_path / "phong.exr").exists()


def test_a_missing_spec_file_raises_an_io_error_naming_it(tmp_path):
    with pytest.raises(brdfbake.IoError) as caught:
        brdfbake.bake(tmp_path / "nowhere.json", progress=False)
    assert "nowhere.json" in str(caught.value) and isinstance(caught.value, OSError)


def test_outputs_leaving_out_dir_or_colliding_are_refused_before_any_work(tmp_path):
    with pytest.raises(brdfbake.InvalidArgumentError, match="output folder"):
        brdfbake.bake({"maps": [dict(PHONG_EYE, output="../escape.exr")]}, out_dir=tmp_path / "out", progress=False)
    with pytest.raises(brdfbake.InvalidInputError, match=r"spec: maps\[1\]\.output: same file as maps\[0\]\.output"):
        brdfbake.bake({"maps": [PHONG_EYE, PHONG_EYE]}, out_dir=tmp_path, progress=False)
    assert not (tmp_path / "escape.exr").exists() and not (tmp_path / "phong_eye.exr").exists()


def test_bad_arguments_raise_errors_not_crashes(tmp_path):
    with pytest.raises(brdfbake.InvalidArgumentError, match="threads"):
        brdfbake.bake({"maps": [PHONG_EYE]}, out_dir=tmp_path, threads=-1, progress=False)
    with pytest.raises(TypeError):
        brdfbake.bake(42, progress=False)
    with pytest.raises(TypeError, match="progress"):
        brdfbake.bake({"maps": [PHONG_EYE]}, out_dir=tmp_path, progress="yes")
    assert list(tmp_path.iterdir()) == []


def test_a_lambertian_sphere_map_lit_from_the_eye_holds_the_albedo_times_n_z(tmp_path):
    # Phong's diffuse term alone, light at the eye (l = v = +z): the value is albedo * max(0, n.l) = albedo * n_z,
    # n_z = sqrt(1 - x^2 - y^2) at the texel (docs/conventions.md). A texel holds the mean over its
    # footprint: off its centre value by about h^2/24 |laplacian n_z| (h = 2/N), below 2e-4 of the
    # albedo inside radius 0.9 at N = 128.
    albedo = [0.2, 0.5, 0.8]
    spec = {"maps": [{"output": "lambert.exr", "parameterization": "sphere", "resolution": 128,
                      "material": {"model": "phong", "specular": 0, "exponent": 1, "diffuse": albedo},
                      "lights": [{"direction": "eye"}]}]}
    brdfbake.bake(spec, out_dir=tmp_path, progress=False)
    pixels = brdfbake.read_map(tmp_path / "lambert.exr").pixels
    n = 128
    j, i = np.mgrid[0:n, 0:n]
    x, y = 2 * (i + 0.5) / n - 1, 2 * (1 - (j + 0.5) / n) - 1
    inside = np.hypot(x, y) < 0.9
    n_z = np.sqrt(1 - x[inside] ** 2 - y[inside] ** 2)
    for c, a in enumerate(albedo):
        assert np.max(np.abs(pixels[inside][:, c] - a * n_z)) < 2e-4 * a
    # The centre texels, n_z ~ 1, hold the albedo itself.
    assert np.allclose(pixels[63:65, 63:65, :3], albedo, rtol=2e-4, atol=0)


def test_a_map_failing_while_made_does_not_stop_the_others_and_is_raised_with_them(tmp_path):
    # An `auto` bound no configuration meets fails while the map is made (docs/spec.md), after the spec
    # was checked whole: the next map is still written, and the error names maps[0].
    unreachable = dict(PHONG_EYE, output="unreachable.exr", resolution="auto", samples_per_texel=1, max_error=1e-9,
                       material={"model": "phong", "exponent": 5000})
    fine = dict(PHONG_EYE, output="fine.exr", resolution=16)
    with pytest.raises(brdfbake.InvalidInputError) as caught:
        brdfbake.bake({"maps": [unreachable, fine]}, out_dir=tmp_path, progress=False)
    assert str(caught.value).startswith("spec: maps[0]: no configuration meets max_error 1e-09")
    result = caught.value.result
    assert isinstance(result, brdfbake.BakeResult) and result.failed == 1
    assert [m.written for m in result.maps] == [False, True] and result.maps[0].error in str(caught.value)
    assert result.to_json()["maps"][0]["status"] == "failed"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fine.exr"]


@pytest.mark.parametrize("threads, error", [(1.5, TypeError), ("2", TypeError), (True, TypeError),
                                            (10**12, brdfbake.InvalidArgumentError), (5000, brdfbake.InvalidArgumentError)])
def test_integer_keywords_of_the_wrong_type_or_size_are_errors_naming_them(tmp_path, threads, error):
    with pytest.raises(error, match="threads"):
        brdfbake.bake({"maps": [PHONG_EYE]}, out_dir=tmp_path, threads=threads, progress=False)
    with pytest.raises(brdfbake.InvalidArgumentError, match="spec: an empty path"):
        brdfbake.bake("", progress=False)
    assert list(tmp_path.iterdir()) == []
    assert brdfbake.bake({"maps": [dict(PHONG_EYE, resolution=8)]}, out_dir=tmp_path, threads=np.int32(1),
                         progress=False).failed == 0
