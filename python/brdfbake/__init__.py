"""brdfbake: bake reflectance functions into environment maps, fit measured BRDFs, prefilter environments.

The Python front of the brdfbake library (docs/python.md). Each function is one job of the library's
run layer, the same call the ``brdfbake`` tool makes for its command, with the same results:

- :func:`bake` runs a spec (a file or a dict in the JSON spec's form), like ``brdfbake bake``;
- :func:`read_map` reads any output back: ``.pixels`` as numpy, ``.sample(dirs)`` as ``brdfbake sample``;
- :func:`fit` fits lobes to a measured table, like ``brdfbake fit``;
- :func:`prefilter` prefilters an environment (a file or a numpy lat-long image), like ``brdfbake prefilter``.

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
import tempfile
from collections.abc import Mapping
from contextlib import ExitStack
from typing import Any, Optional, Sequence, Union

from . import _core
from ._core import BakeResult, Fit, Map, MapResult, read_map
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
    with progress_callback(progress) as callback:
        return _core.fit_table(
            table, lobes, kind, elevation, method, max_exponent, varying_prior, color_profile, half_difference,
            held_out, folds, channels, rgb, format, output, report, threads, callback,
        )


# The spec keys a prefilter request sets, named by prefilter()'s keywords in messages.
_PREFILTER_KEYWORDS = [
    ("prefilter: maps[0].environment.gloss_chain.scale", "prefilter: gloss_scale"),
    ("prefilter: maps[0].environment.gloss_chain.bias", "prefilter: gloss_bias"),
    ("prefilter: maps[0].environment.gloss_chain.levels", "prefilter: mip_count"),
    ("prefilter: maps[0].environment.gloss_chain", "prefilter: gloss_scale"),
    ("prefilter: maps[0].environment.file", "prefilter: environment"),
    ("prefilter: maps[0].environment.lobe", "prefilter: lobe"),
    ("prefilter: maps[0].environment.method", "prefilter: method"),
    ("prefilter: maps[0].environment.max_error", "prefilter: max_error"),
    ("prefilter: maps[0].environment.from", "prefilter: from_"),
    ("prefilter: maps[0].environment.view", "prefilter: view"),
    ("prefilter: maps[0].environment.up", "prefilter: up"),
    ("prefilter: maps[0].environment.elevations", "prefilter: elevations"),
    ("prefilter: maps[0].environment.fresnel", "prefilter: fresnel_ior"),
    ("prefilter: maps[0].environment.combine", "prefilter: combine"),
    ("prefilter: maps[0].environment.sh_output", "prefilter: sh_output"),
    ("prefilter: maps[0].environment.mip_layout", "prefilter: tiled"),
    ("prefilter: maps[0].environment.mips", "prefilter: mips"),
    ("prefilter: maps[0].environment", "prefilter"),
    ("prefilter: maps[0].output", "prefilter: output"),
    ("prefilter: maps[0].resolution", "prefilter: resolution"),
    ("prefilter: maps[0].parameterization", "prefilter: to"),
    ("prefilter: maps[0].samples_per_texel", "prefilter: samples_per_texel"),
    ("prefilter: maps[0].layout", "prefilter: faces"),
    ("prefilter: maps[0]", "prefilter"),
    ('"mips"', "mips"),
    ('"fresnel"', "fresnel_ior"),
    ('"lobe": "irradiance"', 'lobe="irradiance"'),
]


def _renamed(error: Error, replacements: Sequence[tuple[str, str]]) -> Error:
    message = error.message
    for old, new in replacements:
        message = message.replace(old, new)
    if message == error.message:
        return error
    renamed = type(error)(message, result=error.result)
    return renamed


def prefilter(
    environment: Union[PathLike, Any],
    lobe: str,
    to: str,
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
    gloss_scale: Optional[float] = None,
    gloss_bias: Optional[float] = None,
    mip_count: Optional[int] = None,
    edge_fixup: bool = True,
    sh_output: Optional[PathLike] = None,
    threads: int = 0,
    progress: Progress = None,
) -> Map:
    """Prefilters an environment with a lobe into a map, as ``brdfbake prefilter`` does (docs/prefilter.md).

    environment: an image file (EXR, HDR, ...; a cube as six files STEM_posx.EXT ...: pass STEM.EXT), or a
        numpy array of radiance: a lat-long image (H, 2H, 3) (or 4 channels; float32, row 0 at the top,
        the centre looking down -z), or another layout with from_. An array is written to a temporary
        OpenEXR file, removed afterwards.
    lobe: mirror | irradiance | phong:N | blinn:N | ggx:ROUGHNESS | lobes:FIT.json.
    to: sphere | paraboloid | cube | latlong. resolution: texels per side, hemisphere, face, or rows.
    output: the map's file; None keeps the map in memory only (a temporary file, removed), which the
        options writing more files beside it (mips, faces, sh_output, fresnel_ior) need.
    The other keywords are the tool's flags (``brdfbake prefilter --help``) and the spec keys of an
    environment map (docs/spec.md). threads, progress: as for bake().

    Returns the Map read back from the file written; Map.result is the map's entry as
    ``prefilter --json`` prints it (method chosen, error estimate). Errors name the keyword.
    """
    resolution, samples_per_texel, threads = (_whole(resolution, "resolution"),
                                              _whole(samples_per_texel, "samples_per_texel"), _whole(threads, "threads"))
    elevations, mip_count = _whole(elevations, "elevations", True), _whole(mip_count, "mip_count", True)
    with ExitStack() as cleanup:
        renames = list(_PREFILTER_KEYWORDS)
        if not isinstance(environment, (str, os.PathLike)):
            folder = cleanup.enter_context(tempfile.TemporaryDirectory(prefix="brdfbake-"))
            path = os.path.join(folder, "environment.exr")
            _core.write_environment(environment, path)
            renames.append((path, "environment array"))
            environment = path
            from_ = from_ or "latlong"
        if output is None:
            beside = [name for name, value in (("mips", mips), ("faces", faces), ("sh_output", sh_output),
                                               ("fresnel_ior", fresnel_ior)) if value]
            if beside:
                raise InvalidArgumentError(f"prefilter: {beside[0]} writes files beside the map: give output=PATH")
            folder = cleanup.enter_context(tempfile.TemporaryDirectory(prefix="brdfbake-"))
            output = os.path.join(folder, "prefiltered.exr")
            renames.append((output, "the in-memory map"))
        try:
            with progress_callback(progress) as callback:
                return _core.prefilter_environment(
                    environment, lobe, to, resolution, output, method, max_error, from_, mips, tiled, faces, view,
                    up, samples_per_texel, elevations, fresnel_ior, combine, gloss_scale, gloss_bias, mip_count,
                    edge_fixup, sh_output, threads, callback,
                )
        except Error as error:
            raise _renamed(error, renames) from None

