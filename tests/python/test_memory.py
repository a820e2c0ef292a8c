"""prefilter, matcap and ibl in memory: numpy arrays in and out, no file written or read but the inputs
named, from a read-only working folder with TMPDIR pointing nowhere; an Environment prepared once serves
many calls; cube maps come out as (6, N, N, 4) in OpenGL face order (docs/conventions.md), checked
against values computed here."""

import math
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import brdfbake


def linear_sky(h=32):
    """Radiance 1 + y over a lat-long image: row j at polar angle pi (j + 0.5) / h from +y."""
    theta = np.pi * (np.arange(h) + 0.5) / h
    sky = np.empty((h, 2 * h, 3), dtype=np.float32)
    sky[:] = (1 + np.cos(theta))[:, None, None]
    return sky


def face_directions(n):
    """The unit directions of every texel centre of an n^2 cube, faces +X, -X, +Y, -Y, +Z, -Z, as the
    OpenGL table lays them out (s right, t down): (6, n, n, 3)."""
    c = (np.arange(n) + 0.5) / n * 2 - 1
    s, t = np.meshgrid(c, c)  # s along columns, t along rows
    one = np.ones_like(s)
    faces = [(one, -t, -s), (-one, -t, s), (s, one, t), (s, -one, -t), (s, -t, one), (-s, -t, -one)]
    d = np.stack([np.stack(f, axis=-1) for f in faces])
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def test_nothing_is_written_or_needed_but_the_arrays(tmp_path):
    # A child interpreter in a read-only folder, TMPDIR a path that does not exist: every call works.
    folder = tmp_path / "readonly"
    folder.mkdir()
    script = textwrap.dedent("""
        import numpy as np, brdfbake
        h = 32
        theta = np.pi * (np.arange(h) + 0.5) / h
        sky = np.empty((h, 2 * h, 3), np.float32)
        sky[:] = (1 + np.cos(theta))[:, None, None]
        env = brdfbake.Environment(sky)
        m = brdfbake.matcap({"model": "phong", "diffuse": [0.5] * 3, "specular": [0] * 3, "exponent": 1}, env, 32)
        p = brdfbake.prefilter(env, "irradiance", "cube", 8)
        i = brdfbake.ibl(env, resolution=32, skybox_resolution=16)
        b = brdfbake.bake({"maps": [{"parameterization": "sphere", "resolution": 16, "material": {"model": "phong", "exponent": 5},
                                     "lights": [{"direction": "eye"}]}]}).maps[0].map
        print(m.pixels.shape, p.pixels.shape, i.specular[0].shape, len(i.specular), i.sh.shape, b.pixels.shape)
    """)
    os.chmod(folder, 0o555)
    try:
        env = dict(os.environ, TMPDIR=str(tmp_path / "nowhere"))
        done = subprocess.run([sys.executable, "-c", script], cwd=folder, env=env, capture_output=True, text=True,
                              timeout=300)
    finally:
        os.chmod(folder, 0o755)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "(32, 32, 4) (24, 32, 4) (6, 32, 32, 4) 6 (9, 3) (16, 16, 4)"
    assert list(folder.iterdir()) == []


def test_an_environment_array_is_read_as_the_lat_long_image_it_is():
    sky = linear_sky()
    env = brdfbake.Environment(sky)
    assert env.parameterization == "latlong" and env.resolution == 32 and env.source == "environment array"
    assert np.array_equal(env.pixels[:, :, :3], sky) and np.all(env.pixels[:, :, 3] == 1)
    with pytest.raises(ValueError):
        env.pixels[0, 0, 0] = 2  # a read-only view


def test_ibl_cube_faces_follow_the_opengl_order_and_hold_the_filtered_sky():
    # A normalised lobe of mean cosine kappa filters 1 + y into 1 + kappa r.y; E/pi is 1 + (2/3) n.y; the
    # skybox is the sky itself. Each face of each array is checked at its own texel centres.
    ibl = brdfbake.ibl(linear_sky(64), resolution=16, irradiance_resolution=8, skybox_resolution=16, dfg_size=16,
                       progress=False)
    assert [level.shape for level in ibl.specular] == [(6, n, n, 4) for n in (16, 8, 4, 2, 1)]
    # Interior texels to 0.5 %; edge texels are averaged with the texel across the edge (edge fixup), which
    # moves them by up to half the step between neighbours.
    def check(faces, expected):
        error = np.abs(faces[..., 0] - expected)
        assert np.max(error[:, 1:-1, 1:-1]) < 0.005 * 2 and np.max(error) < 0.05

    check(ibl.skybox, 1 + face_directions(16)[..., 1])
    check(ibl.irradiance, 1 + 2 / 3 * face_directions(8)[..., 1])
    mirror = ibl.specular[0][..., 0]  # level 0: roughness 0, the sky resampled, no edge fixup in the chain
    assert np.max(np.abs(mirror - (1 + face_directions(16)[..., 1]))) < 0.01
    # The SH of E/pi = 1 + (2/3) y: Y00 = 1/(2 sqrt pi), Y1-1 = -sqrt(3/(4 pi)) y (orthonormal, with the
    # Condon-Shortley phase: maps/sh.hpp; the file's "basis" says so).
    y00, y1 = 0.5 / math.sqrt(math.pi), -math.sqrt(3 / (4 * math.pi))
    assert ibl.sh[0, 0] == pytest.approx(1 / y00, rel=0.01)
    assert ibl.sh[1, 0] == pytest.approx(2 / 3 / y1, rel=0.01)
    assert ibl.dfg.shape == (16, 16, 2)


def test_ibl_saves_the_files_the_tool_writes(tmp_path):
    ibl = brdfbake.ibl(linear_sky(), resolution=8, irradiance_resolution=16, skybox_resolution=8, dfg_size=8,
                       progress=False)
    report = ibl.save(tmp_path, format="exr", stem="sky")
    roles = {f["role"]: f["file"] for f in report["files"]}
    assert sorted(roles) == ["dfg", "irradiance", "irradiance_sh", "skybox", "specular"]
    for file in roles.values():
        assert os.path.exists(file)
    back = brdfbake.read_map(roles["irradiance"])
    assert np.allclose(back.sample([0, 1, 0])[0], 1 + 2 / 3, rtol=0.02)
    with pytest.raises(brdfbake.Error, match="format: "):
        ibl.save(tmp_path / "bad", format="png")
    assert not (tmp_path / "bad").exists()


def test_a_matcap_saved_later_is_the_map_in_memory(tmp_path):
    env = brdfbake.Environment(linear_sky())
    m = brdfbake.matcap({"model": "phong", "diffuse": [0.5] * 3, "specular": [0] * 3, "exponent": 1}, env, 64,
                        max_error=0.01, progress=False)
    assert m.path is None and m.files == []
    # A grey Lambertian under 1 + y: L_o = 0.5 E/pi = 0.5 (1 + (2/3) n.y), n = normalize(r + v) the normal a
    # sphere map's lookup direction r stands for (view v = +z; the camera's frame is the environment's).
    for r in ([0, 0, 1], [0, 1, 1], [0.5, -0.5, 0.7]):
        n = np.array(r) / np.linalg.norm(r) + [0, 0, 1]
        n /= np.linalg.norm(n)
        assert m.sample(r)[0] == pytest.approx(0.5 * (1 + 2 / 3 * n[1]), rel=0.02), r
    files = m.save(tmp_path / "m.exr")
    assert files == [tmp_path / "m.exr"] and m.files == files
    assert np.array_equal(brdfbake.read_map(tmp_path / "m.exr").pixels, m.pixels)
    assert brdfbake.read_map(tmp_path / "m.exr").metadata["spec"]["environment"]["file"] == "environment array"


def test_a_spec_map_without_output_is_made_in_memory(tmp_path):
    # The analytic Phong map lit from the eye (as test_bake.py's file route): max(0, r_z)^n at every map
    # direction r, within 1 % of the peak away from the rim; no file written; save() writes it later.
    phong = {"parameterization": "sphere", "resolution": 256, "samples_per_texel": 16,
             "material": {"model": "phong", "specular": [1, 1, 1], "exponent": 50},
             "lights": [{"direction": "eye", "color": [1, 1, 1]}]}
    written = dict(phong, output="written.exr")
    result = brdfbake.bake({"maps": [phong, written]}, out_dir=tmp_path, progress=False)
    kept, on_disk = result.maps
    assert kept.files == [] and str(kept.output) in ("", ".")
    assert kept.to_json()["status"] == "in_memory" and kept.written
    assert on_disk.map is None and [p.name for p in result.files] == ["written.exr"]
    assert "made maps[0] in memory (sphere 256x256" in result.brief_report()
    rng = np.random.default_rng(7)
    dirs = rng.normal(size=(20000, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    dirs = dirs[dirs[:, 2] > -math.cos(math.radians(10))]
    values = kept.map.sample(dirs)
    assert np.max(np.abs(values[:, :3] - np.maximum(0.0, dirs[:, 2:3]) ** 50)) < 0.01
    assert kept.map.metadata["spec"]["material"]["exponent"] == 50
    assert np.array_equal(kept.map.pixels, brdfbake.read_map(tmp_path / "written.exr").pixels)
    assert kept.map.save(tmp_path / "later.exr") == [tmp_path / "later.exr"]
    assert np.array_equal(brdfbake.read_map(tmp_path / "later.exr").pixels, kept.map.pixels)
    # A map made in memory writes nothing of its own: what would be files beside it is refused by name.
    silhouette = {"parameterization": "sphere", "resolution": 64, "material": {"model": "silhouette", "width": 10}, "mips": True}
    with pytest.raises(brdfbake.Error, match=r"maps\[0\]\.mips: mip levels are files .*name an \"output\""):
        brdfbake.bake({"maps": [silhouette]}, progress=False)
    with pytest.raises(brdfbake.Error, match=r"maps\[0\]\.parameterization: a radial profile"):
        brdfbake.bake({"maps": [dict(phong, parameterization="profile")]}, progress=False)


def test_errors_name_the_keyword():
    env = brdfbake.Environment(linear_sky())
    material = {"model": "phong", "specular": [1, 1, 1], "exponent": 10}
    for call, words in [
        (lambda: brdfbake.matcap(material, env, 0), "resolution: "),
        (lambda: brdfbake.matcap(material, env, 16, max_error=2.0), "max_error: "),
        (lambda: brdfbake.matcap(material, env, 16, max_relative_error=0.0), "max_relative_error: must be in (0, 10]"),
        (lambda: brdfbake.matcap({"model": "gooch"}, env, 16), "material: gooch has no BRDF"),
        (lambda: brdfbake.matcap({"model": "nope"}, env, 16), "material: model: unknown model"),
        (lambda: brdfbake.matcap(material, env, 16, camera=(0, 120)), "camera: "),
        (lambda: brdfbake.ibl(env, resolution=24), "resolution: must be a power of two"),
        (lambda: brdfbake.prefilter(env, "ggx:2", "cube", 8), "lobe: "),
    ]:
        with pytest.raises(brdfbake.Error) as caught:
            call()
        assert str(caught.value).startswith(words), str(caught.value)
    with pytest.raises(TypeError):
        brdfbake.matcap(42, env, 16)
