"""brdfbake.fit: the fit.json the tool writes for the same table and options, evaluation equal to
`brdfbake eval` and to the model's formula typed out here, and bad input raising brdfbake.Error."""

import json
import math

import numpy as np
import pytest

import brdfbake
from conftest import run_cli, without_keys

# Wall times and the generator's own run time differ from run to run; nothing else may.
TIMINGS = {"seconds"}


@pytest.fixture(scope="module")
def table(source_dir):
    return source_dir / "data_samples" / "tables" / "synthetic_two_lobes.astm"


def same_fit_documents(a, b):
    a, b = without_keys(a, TIMINGS), without_keys(b, TIMINGS)
    assert a == b


def test_a_fit_gives_the_tools_fit_json(table, cli, tmp_path):
    run_cli(cli, "fit", table, "-o", tmp_path / "tool.json", "--threads", 2)
    fit = brdfbake.fit(table, threads=2, progress=False)
    fit.save(tmp_path / "module.json")
    tool = json.loads((tmp_path / "tool.json").read_text())
    same_fit_documents(json.loads((tmp_path / "module.json").read_text()), tool)
    same_fit_documents(fit.document, tool)
    assert fit.usable and fit.samples == 1439 and fit.channel_names == ["R", "G", "B"]
    assert without_keys(fit.held_out, TIMINGS) == without_keys(tool["fit"]["held_out"], TIMINGS)
    assert without_keys(fit.candidates, TIMINGS) == without_keys(tool["fit"]["candidates"], TIMINGS)
    assert fit.held_out_score == pytest.approx(tool["fit"]["held_out"]["score"], rel=1e-12)
    assert fit.in_sample_error == tool["fit"]["in_sample_log_error"]
    assert fit.lobes == [c["lobes"] for c in tool["channels"]] and fit.model == tool["model"]
    assert "held-out" in fit.brief_report()


def test_options_and_the_json_report_match_the_tools(table, cli, tmp_path):
    # Every choice explicit (elevation too), so no held-out estimate is made.
    tool = run_cli(cli, "fit", table, "--lobes", 1, "--kind", "mirror", "--elevation", "constant", "--held-out", "off",
                   "--max-exponent", 500, "--threads", 1)
    fit = brdfbake.fit(table, lobes=1, kind="mirror", elevation="constant", held_out=False, max_exponent=500, threads=1,
                       progress=False)
    ours = fit.to_json()
    assert set(ours) == set(tool)
    same_fit_documents(ours, tool)
    assert fit.held_out is None and fit.held_out_score is None
    assert len(fit.lobes[0]) == 1 and fit.lobes[0][0]["exponent"][0] <= 500


def test_evaluate_gives_the_model_formula_and_the_tools_eval(table, cli, tmp_path):
    fit = brdfbake.fit(table, lobes=2, kind="mirror", elevation="constant", held_out=False, progress=False)
    fit.save(tmp_path / "fit.json")
    rng = np.random.default_rng(5)
    wi = rng.normal(size=(400, 3))
    wo = rng.normal(size=(400, 3)) * [1, 1, 3]
    values = fit.evaluate(wi, wo)
    assert values.shape == (400, 3)
    # docs/fitting.md: f(l, v) = k_d/pi + sum_k C_k (n_k + 2)/(2 pi) max(0, r_v . l)^n_k, r_v the view
    # mirrored about the normal, 0 with either direction at or below the horizon.
    l = wi / np.linalg.norm(wi, axis=1, keepdims=True)
    v = wo / np.linalg.norm(wo, axis=1, keepdims=True)
    r = v * [-1, -1, 1]
    above = (l[:, 2] > 0) & (v[:, 2] > 0)
    for c, channel in enumerate(fit.channels):
        expected = np.full(len(l), channel["diffuse"] / math.pi)
        for lobe in channel["lobes"]:
            n, weight = lobe["exponent"][0], lobe["weight"][0]
            expected += weight * (n + 2) / (2 * math.pi) * np.maximum(0.0, np.sum(r * l, axis=1)) ** n
        expected[~above] = 0.0
        assert np.allclose(values[:, c], expected, rtol=1e-12, atol=1e-14)
    for k in (0, 1, 2, int(np.argmax(above))):
        tool = run_cli(cli, "eval", tmp_path / "fit.json", "--wi", ",".join(map(repr, wi[k])),
                       "--wo", ",".join(map(repr, wo[k])))
        assert np.allclose(values[k], tool["value"], rtol=1e-12, atol=0)
    assert fit.evaluate(wi[0], wo[0]).shape == (3,)
    assert np.allclose(fit.evaluate(wi[0], wo[:5]), fit.evaluate(np.tile(wi[0], (5, 1)), wo[:5]))


def test_colour_profiles_follow_the_formula_in_theta_d(table):
    fit = brdfbake.fit(table, lobes=1, kind="mirror", elevation="constant", color_profile="difference_angle",
                       held_out=False, progress=False)
    assert fit.model["color_profile"] == "difference_angle"
    rng = np.random.default_rng(7)
    l = rng.normal(size=(300, 3)) * [1, 1, 2]
    v = rng.normal(size=(300, 3)) * [1, 1, 2]
    l[:, 2], v[:, 2] = np.abs(l[:, 2]) + 0.05, np.abs(v[:, 2]) + 0.05
    l /= np.linalg.norm(l, axis=1, keepdims=True)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    values = fit.evaluate(l, v)
    # docs/fitting.md: every weight times sum_j p_j binom(3, j) s^j (1 - s)^(3 - j), s = theta_d / 90 degrees,
    # theta_d the angle between l and the half-vector.
    h = (l + v) / np.linalg.norm(l + v, axis=1, keepdims=True)
    s = np.arccos(np.clip(np.sum(l * h, axis=1), -1, 1)) / (math.pi / 2)
    bernstein = np.stack([(1 - s) ** 3, 3 * s * (1 - s) ** 2, 3 * s ** 2 * (1 - s), s ** 3], axis=1)
    r = v * [-1, -1, 1]
    for c, channel in enumerate(fit.channels):
        expected = channel["diffuse"] * (bernstein @ channel["diffuse_profile"]) / math.pi
        lobe = channel["lobes"][0]
        n = lobe["exponent"][0]
        expected += (lobe["weight"][0] * (bernstein @ lobe["weight_profile"]) * (n + 2) / (2 * math.pi)
                     * np.maximum(0.0, np.sum(r * l, axis=1)) ** n)
        assert np.allclose(values[:, c], expected, rtol=1e-10, atol=1e-14)


def test_the_half_difference_table_follows_its_formula(table):
    fit = brdfbake.fit(table, kind="half_difference", held_out=False, progress=False)
    shape = fit.model["half_difference"]
    knots, degree = shape["half_angle_knots"], shape["difference_degree"]
    rng = np.random.default_rng(11)
    l, v = rng.normal(size=(300, 3)), rng.normal(size=(300, 3))
    l[:, 2], v[:, 2] = np.abs(l[:, 2]) + 0.05, np.abs(v[:, 2]) + 0.05
    l /= np.linalg.norm(l, axis=1, keepdims=True)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    values = fit.evaluate(l, v)
    # docs/fitting.md: ln f = sum_kj a_kj hat_k(sqrt(theta_h / 90 deg) (K - 1)) B_j(theta_d / 90 deg), index k (D + 1) + j.
    h = (l + v) / np.linalg.norm(l + v, axis=1, keepdims=True)
    x = np.sqrt(np.arccos(np.clip(h[:, 2], -1, 1)) / (math.pi / 2)) * (knots - 1)
    s = np.arccos(np.clip(np.sum(l * h, axis=1), -1, 1)) / (math.pi / 2)
    hats = np.maximum(0.0, 1.0 - np.abs(x[:, None] - np.arange(knots)[None, :]))
    bernstein = np.stack([math.comb(degree, j) * s ** j * (1 - s) ** (degree - j) for j in range(degree + 1)], axis=1)
    basis = (hats[:, :, None] * bernstein[:, None, :]).reshape(len(x), -1)
    for c, channel in enumerate(fit.channels):
        assert len(channel["half_difference"]) == knots * (degree + 1)
        assert np.allclose(values[:, c], np.exp(basis @ channel["half_difference"]), rtol=1e-10, atol=0)


def test_half_difference_none_leaves_the_table_out(cornell):
    table = cornell / "krylon_blue_RGB.astm"
    with_table = brdfbake.fit(table, threads=2, progress=False)
    without = brdfbake.fit(table, half_difference="none", threads=2, progress=False)
    assert [c["kind"] for c in with_table.candidates].count("half_difference") == 1
    assert "half_difference" not in [c["kind"] for c in without.candidates]


def test_a_cornell_table_fits_as_the_tool_fits_it(cornell, cli, tmp_path):
    table = cornell / "krylon_blue_RGB.astm"
    tool = run_cli(cli, "fit", table, "--threads", 2)
    fit = brdfbake.fit(table, threads=2, progress=False)
    same_fit_documents(fit.to_json(), tool)
    assert fit.held_out["kfold"]["ratio_to_lambert"] < 1


@pytest.mark.parametrize(
    "options, error, words",
    [
        ({"lobes": 9}, brdfbake.InvalidArgumentError, r"lobes: expected \"auto\" or a whole number in \[1, 6\]"),
        ({"lobes": 1.5}, brdfbake.InvalidArgumentError, "lobes: "),
        ({"lobes": True}, brdfbake.InvalidArgumentError, "lobes: "),
        ({"kind": "bogus"}, brdfbake.InvalidArgumentError, "kind: "),
        ({"method": "bogus"}, brdfbake.InvalidArgumentError, "method: "),
        ({"elevation": "bogus"}, brdfbake.InvalidArgumentError, "elevation: "),
        ({"format": "bogus"}, brdfbake.InvalidArgumentError, "format: "),
        ({"max_exponent": 0.5}, brdfbake.InvalidArgumentError, "max_exponent: "),
        ({"varying_prior": -1}, brdfbake.InvalidArgumentError, "varying_prior: "),
        ({"varying_prior": "weak"}, brdfbake.InvalidArgumentError, "varying_prior: "),
        ({"folds": 1}, brdfbake.InvalidArgumentError, "folds: "),
        ({"channels": "cmyk"}, brdfbake.InvalidArgumentError, "channels: "),
        ({"rgb": "srgb"}, brdfbake.InvalidArgumentError, "rgb: "),
        ({"channels": "spectral"}, brdfbake.InvalidArgumentError, "spectral"),
        ({"color_profile": "theta_h"}, brdfbake.InvalidArgumentError, "color_profile: "),
        ({"half_difference": "yes"}, brdfbake.InvalidArgumentError, "half_difference: expected auto or none"),
        ({"method": "per_channel", "color_profile": "difference_angle"}, brdfbake.InvalidArgumentError,
         "colour profiles are fitted by the shared method only"),
    ],
)
def test_bad_options_raise_errors_naming_them(table, options, error, words):
    with pytest.raises(error, match=words):
        brdfbake.fit(table, progress=False, **options)


def test_bad_tables_raise_errors_naming_the_file(tmp_path):
    with pytest.raises(brdfbake.IoError, match="nowhere.astm"):
        brdfbake.fit(tmp_path / "nowhere.astm", progress=False)
    (tmp_path / "bad.astm").write_text("NUM_POINTS 3\nVARS theta_i,phi_i,theta_s,phi_s,R\n\n0.1,0,0.1,nan,1\n")
    with pytest.raises(brdfbake.InvalidInputError, match="bad.astm"):
        brdfbake.fit(tmp_path / "bad.astm", progress=False)


def test_save_never_overwrites_the_table(table, tmp_path):
    (tmp_path / "table.astm").write_bytes(table.read_bytes())
    fit = brdfbake.fit(tmp_path / "table.astm", lobes=1, held_out=False, progress=False)
    with pytest.raises(brdfbake.InvalidArgumentError, match="table"):
        fit.save(tmp_path / "table.astm")
    assert (tmp_path / "table.astm").read_bytes() == table.read_bytes()
    with pytest.raises(brdfbake.InvalidArgumentError, match="wi"):
        fit.evaluate([[0, 0, 1], [0, 0, 0]], [0, 0, 1])
    with pytest.raises(brdfbake.InvalidArgumentError, match="wi and wo"):
        fit.evaluate(np.ones((3, 3)), np.ones((2, 3)))
