"""brdfbake: bake reflectance functions into environment maps, fit measured BRDFs, prefilter environments.

The Python front of the brdfbake library (docs/python.md). Each function is one job of the library's
run layer, the same call the ``brdfbake`` tool makes for its command, with the same results:

- :func:`bake` runs a spec (a file or a dict in the JSON spec's form), like ``brdfbake bake``;
- :func:`read_map` reads any output back: ``.pixels`` as numpy, ``.sample(dirs)`` as ``brdfbake sample``;
- :func:`fit` fits lobes to a measured table, like ``brdfbake fit``;
- :func:`prefilter` prefilters an environment, like ``brdfbake prefilter``;
- :func:`matcap` shades a material under an environment, like ``brdfbake matcap``;
- :func:`ibl` makes engine-ready image-based lighting, like ``brdfbake ibl``;
- :class:`Environment` loads an environment (a file, or a numpy array) once for many of these.

prefilter, matcap and ibl work in memory: nothing is written unless an output is named (or ``save`` is
called), and numpy arrays go in and come out without temporary files.

Bad input raises :class:`Error` (a subclass per kind) whose message names the file, line, JSON path or
keyword. Long work runs without the GIL, shows progress (``progress=``) and stops cleanly on Ctrl-C
(KeyboardInterrupt; the output being written is removed, outputs already complete stay).

    >>> import brdfbake
    >>> spec = {"maps": [{"output": "phong.exr", "parameterization": "sphere", "resolution": 64,
    ...          "material": {"model": "phong", "specular": [1, 1, 1], "exponent": 50},
    ...          "lights": [{"direction": "eye", "color": [1, 1, 1]}]}]}
    >>> result = brdfbake.bake(spec, out_dir="out")
    >>> brdfbake.read_map("out/phong.exr").sample([0, 0.3, 1])
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any, Optional, Sequence, Union

from . import _core
from ._core import BakeResult, Environment, Fit, Ibl, Map, MapResult, read_map
from ._errors import (
    Error,
    InvalidArgumentError,
    InvalidInputError,
    IoError,
    NumericalError,
    ResourceError,
    error_class,
)
from ._progress import Progress, ProgressCallback, progress_callback

__version__: str = _core.version

__all__ = [
    "bake",
    "read_map",
    "fit",
    "prefilter",
    "matcap",
    "ibl",
    "Environment",
    "Ibl",
    "Map",
    "Fit",
    "BakeResult",
    "MapResult",
    "Error",
    "InvalidArgumentError",
    "InvalidInputError",
    "IoError",
    "ResourceError",
    "NumericalError",
    "ProgressCallback",
    "__version__",
]

PathLike = Union[str, "os.PathLike[str]"]


def _whole(value: Any, keyword: str, optional: bool = False) -> Any:
    """`value` of an integer keyword, checked here so that a wrong type or a number beyond 32 bits is
    an error naming the keyword (the library checks the range of the others)."""
    if optional and value is None:
        return value
    if isinstance(value, bool) or not isinstance(value, int):
        try:
            import numpy  # numpy integers are integers

            if isinstance(value, numpy.integer):
                value = int(value)
        except ImportError:
            pass
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{keyword}: expected an int, got {value!r}")
    if not -(2**31) <= value < 2**31:
        raise InvalidArgumentError(f"{keyword}: {value} is out of range")
    return value


def _paths(**keywords: Any) -> None:
    """Path keywords checked for a NUL here, so the error names the keyword (pybind11's path conversion
    would raise a TypeError listing every signature; the library refuses NUL in any path it is given)."""
    for keyword, value in keywords.items():
        if isinstance(value, (str, bytes, os.PathLike)) and "\0" in os.fsdecode(value):
            raise InvalidArgumentError(f"{keyword}: contains a NUL character, which no file name may hold")


def bake(
    spec: Union[PathLike, Mapping[str, Any]],
    out_dir: Optional[PathLike] = None,
    threads: int = 0,
    progress: Progress = None,
    *,
    allow_large: bool = False,
) -> BakeResult:
    """Bakes every map of a spec, as ``brdfbake bake SPEC --out-dir OUT_DIR`` does.

    spec: a spec file, or a dict in the JSON spec's form (docs/spec.md). Relative paths in a file
        resolve against its folder; in a dict against the current folder, its outputs against out_dir
        when given.
    out_dir: write the outputs under this folder (each must stay inside it).
    threads: worker threads, 0 = every core.
    progress: a callable progress(task, fraction), True (tqdm bars, or lines on stderr), False, or None
        (tqdm bars when tqdm is installed and stderr is a terminal).
    allow_large: allow maps over 8192^2 texels (the memory budget still applies).

    A map without "output" is made in memory only: its MapResult.map is a Map (pixels, sample, save),
    and nothing is written for it (docs/python.md).

    The whole spec is checked before any map is made. Returns the BakeResult (to_json() is what
    ``bake --json`` prints). Raises Error naming the JSON path for a bad spec; when a map fails while
    being made the others are still made, and the first failure is raised, naming the map's JSON path,
    with ``.result`` set to the BakeResult of all of them.
    """
    document = spec if isinstance(spec, Mapping) else None
    path = None if document is not None else spec
    if path is not None and isinstance(path, (str, os.PathLike)) and not os.fspath(path):
        raise InvalidArgumentError("spec: an empty path")
    threads = _whole(threads, "threads")
    _paths(spec=path, out_dir=out_dir)
    with progress_callback(progress) as callback:
        result = _core.run_spec(path, document, out_dir, threads, allow_large, "spec", callback)
    failure = result._first_error
    if failure is not None:
        kind, message = failure
        # The first failed map's place in the spec, as the tool's "maps[0] failed: ..." line gives it.
        failed = next((m for m in result.maps if not m.written), None)
        if failed is not None and failed.json_path not in message:
            message = f"{'spec' if document is not None else os.fspath(spec)}: {failed.json_path}: {message}"
        raise error_class(kind)(message, result=result)
    return result


def fit(
    table: PathLike,
    *,
    lobes: Union[int, str] = "auto",
    kind: str = "auto",
    elevation: str = "auto",
    method: str = "shared",
    max_exponent: Union[float, str] = "auto",
    varying_prior: Union[float, str] = "auto",
    color_profile: str = "auto",
    half_difference: str = "auto",
    held_out: bool = True,
    folds: int = 5,
    channels: str = "rgb",
    rgb: str = "cie1931",
    format: str = "auto",
    output: Optional[PathLike] = None,
    report: Optional[PathLike] = None,
    threads: int = 0,
    progress: Progress = None,
) -> Fit:
    """Fits lobes to a measured table, as ``brdfbake fit TABLE`` does (docs/fitting.md).

    table: .astm (Cornell), .brdf (pbrt-v2), .binary (MERL) or .mat; format: auto | astm | pbrt | merl | mat.
    lobes: "auto" or 1..6 per channel. kind: auto | mirror | lafortune | half_vector | mixed | half_difference (a
    half-difference table alone, docs/fitting.md).
    elevation: auto | constant | varying (with the view's elevation). method: shared | per_channel.
    max_exponent: "auto" or a cap in [1, 1e5]. varying_prior: "auto" or a prior in [0, 1] on varying lobes'
    elevation profiles (FitOptions::varyingPrior). color_profile: auto | none | difference_angle (each channel's
    weights times a cubic in theta_d, the angle between light and half-vector; shared method).
    half_difference: auto | none (kind "auto" also scores a half-difference table, docs/fitting.md).
    held_out: estimate the held-out error (auto choices need it); folds: of the off-mirror split, 2..20. channels: rgb | spectral. rgb: cie1931 | single_wavelengths.
    output: also write fit.json there; report: also a PNG of measured against fitted values (gnuplot).
    threads, progress: as for bake().

    Returns a Fit: held_out, lobes, channels, evaluate(wi, wo), save(path) (the fit.json the tool writes),
    to_json() (what ``fit --json`` prints). A fit whose solve failed is returned with usable False.
    """
    threads, folds = _whole(threads, "threads"), _whole(folds, "folds")
    _paths(table=table, output=output, report=report)
    with progress_callback(progress) as callback:
        return _core.fit_table(
            table, lobes, kind, elevation, method, max_exponent, varying_prior, color_profile, half_difference,
            held_out, folds, channels, rgb, format, output, report, threads, callback,
        )


def prefilter(
    environment: Union[PathLike, Any],
    lobe: str = "",
    to: str = "sphere",
    resolution: int = 256,
    *,
    output: Optional[PathLike] = None,
    method: str = "auto",
    max_error: float = 0.01,
    from_: Optional[str] = None,
    mips: bool = False,
    tiled: bool = False,
    faces: bool = False,
    view: Optional[Sequence[float]] = None,
    up: Optional[Sequence[float]] = None,
    samples_per_texel: int = 16,
    elevations: Optional[int] = None,
    fresnel_ior: Optional[float] = None,
    combine: Optional[str] = None,
    chain: Optional[str] = None,
    gloss_scale: Optional[float] = None,
    gloss_bias: Optional[float] = None,
    mip_count: Optional[int] = None,
    edge_fixup: bool = True,
    sh_output: Optional[PathLike] = None,
    threads: int = 0,
    progress: Progress = None,
) -> Map:
    """Prefilters an environment with a lobe into a map, in memory, as ``brdfbake prefilter`` does (docs/prefilter.md).

    environment: an Environment, an image file (EXR, HDR, ...; a cube as six files STEM_posx.EXT ...: pass
        STEM.EXT), or a numpy array of radiance: a lat-long image (H, 2H, 3) (or 4 channels; row 0 at the top,
        the centre looking down -z), or another layout with from_.
    lobe: mirror | irradiance | phong:N | blinn:N | ggx:ROUGHNESS | lobes:FIT.json (phong or blinn with gloss_scale:
        cmft's gloss chain). chain: "ggx" for cmgen's GGX chain (level k of L holds roughness k / (L - 1)).
    to: sphere | paraboloid | cube | latlong. resolution: texels per side, hemisphere, face, or rows.
    output: also write the map there (and its mip levels, faces, Fresnel maps or elevation slices beside it); a
        Fresnel decomposition (fresnel_ior) and a varying fit's elevation stack are several maps and need it.
        Without it nothing is written: Map.save(path) writes the map later.
    The other keywords are the tool's flags (``brdfbake prefilter --help``) and the spec keys of an
    environment map (docs/spec.md). threads, progress: as for bake().

    Returns the Map: .pixels (level 0, a view without a copy), .levels (every mip level), .sample(dirs), and
    .result, the map's summary (method chosen, error estimate). Errors name the keyword.
    """
    resolution, samples_per_texel, threads = (_whole(resolution, "resolution"),
                                              _whole(samples_per_texel, "samples_per_texel"), _whole(threads, "threads"))
    elevations, mip_count = _whole(elevations, "elevations", True), _whole(mip_count, "mip_count", True)
    _paths(environment=environment, output=output, sh_output=sh_output)
    if from_ is not None and isinstance(environment, Environment):
        raise InvalidArgumentError("from_: an Environment knows its parameterization")
    if not isinstance(environment, Environment):
        environment = Environment(environment, from_=from_)
    with progress_callback(progress) as callback:
        return _core.prefilter(
            environment, lobe, to, resolution, output, method, max_error, None, mips, tiled, faces, view, up,
            samples_per_texel, elevations, fresnel_ior, combine, chain, gloss_scale, gloss_bias, mip_count,
            edge_fixup, sh_output, threads, callback,
        )


def matcap(
    material: Union[PathLike, Mapping[str, Any], Fit],
    environment: Union[PathLike, Any],
    resolution: int = 256,
    *,
    max_error: float = 0.01,
    max_relative_error: Optional[float] = None,
    method: str = "auto",
    camera: Optional[Sequence[float]] = None,
    parameterization: str = "sphere",
    samples_per_texel: int = 16,
    exposure: float = 0.0,
    output: Optional[PathLike] = None,
    threads: int = 0,
    progress: Progress = None,
) -> Map:
    """A material shaded under an environment, in memory, as ``brdfbake matcap`` makes it (docs/matcap.md).

    material: a material JSON file, a fit.json or a measured table (.astm, .brdf, .mat: lobes are fitted to it
        first), a dict in a spec's "material" form ({"model": "cook_torrance", ...}), or a Fit.
    environment: an Environment (prepared once: reuse it for many materials), an image file or a numpy array of
        radiance (a lat-long image).
    resolution: texels across. max_error: the bound on the estimated error, RMS relative to the peak (0.05 for a
        live preview, 0.01 for final output: the bound picks the method). max_relative_error: the bound on each
        texel's relative error where the picture is above 1 % of its median (default 3 x max_error).
        camera: (yaw, pitch) in degrees.
    output: also write the map there (format by extension); else Map.save(path) writes it later.

    Returns the Map: .pixels ((N, N, 4) float32, a view), .sample(dirs), .result (the error estimate).
    """
    resolution, samples_per_texel, threads = (_whole(resolution, "resolution"),
                                              _whole(samples_per_texel, "samples_per_texel"), _whole(threads, "threads"))
    _paths(environment=environment, output=output)
    if not isinstance(environment, Environment):
        environment = Environment(environment)
    with progress_callback(progress) as callback:
        return _core.matcap(
            material, environment, resolution, max_error, max_relative_error, method, camera, parameterization,
            samples_per_texel,
            exposure, output, threads, callback,
        )


def ibl(
    environment: Union[PathLike, Any],
    *,
    resolution: int = 256,
    irradiance_resolution: int = 32,
    skybox_resolution: int = 512,
    dfg_size: int = 128,
    dfg_form: str = "single",
    max_error: float = 0.01,
    threads: int = 0,
    progress: Progress = None,
) -> Ibl:
    """Engine-ready image-based lighting, in memory, as ``brdfbake ibl`` makes it (docs/engines.md).

    environment: an Environment, an image file or a numpy array of radiance (a lat-long image).
    resolution: the GGX chain's level-0 face size (a power of two); irradiance_resolution, skybox_resolution:
    their cubes' faces; dfg_size: the DFG table's side; dfg_form: single | multiscatter.

    Returns an Ibl: .specular (one (6, N, N, 4) array per level), .irradiance, .sh ((9, 3)), .dfg, .skybox;
    .save(out_dir, format="ktx2") writes the files the tool writes.
    """
    resolution, irradiance_resolution, skybox_resolution, dfg_size, threads = (
        _whole(resolution, "resolution"), _whole(irradiance_resolution, "irradiance_resolution"),
        _whole(skybox_resolution, "skybox_resolution"), _whole(dfg_size, "dfg_size"), _whole(threads, "threads"))
    if not isinstance(environment, Environment):
        environment = Environment(environment)
    with progress_callback(progress) as callback:
        return _core.ibl(environment, resolution, irradiance_resolution, skybox_resolution, dfg_size, dfg_form,
                         max_error, threads, callback)
