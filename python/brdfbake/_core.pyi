"""Type stubs of brdfbake._core, the extension behind the brdfbake package (python/*.cpp)."""

import os
import pathlib
from typing import Any, Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, os.PathLike[str]]
_Progress = Optional[Callable[[str, float], object]]
_Directions = npt.ArrayLike

version: str

class Environment:
    """Radiance over the sphere, loaded (a file) or wrapped (a numpy array) once, for many jobs."""

    def __init__(self, source: Union[_Path, npt.ArrayLike], from_: Optional[str] = None) -> None: ...
    @property
    def parameterization(self) -> str: ...
    @property
    def resolution(self) -> int: ...
    @property
    def source(self) -> str: ...
    @property
    def detection(self) -> str: ...
    @property
    def pixels(self) -> npt.NDArray[np.float32]:
        """(H, W, 4) float32, read-only, a view without a copy."""

class Map:
    """An output of bake or prefilter read back, or a job's map in memory, as a renderer reads it."""

    @property
    def path(self) -> Optional[pathlib.Path]:
        """Where it was read from or written to; None for a map only in memory."""
    @property
    def kind(self) -> str:
        """map | radial_profile | elevation_stack | fresnel_table | sh_irradiance."""
    @property
    def parameterization(self) -> Optional[str]:
        """sphere | paraboloid | cube | latlong (maps, stacks); profile; fresnel_table; None for SH."""
    @property
    def resolution(self) -> Optional[int]: ...
    @property
    def metadata(self) -> dict[str, Any]:
        """The brdfbake metadata: parameterization, resolution, convention_version, the spec it was made from."""
    @property
    def files(self) -> list[pathlib.Path]: ...
    @property
    def uses_cos_view(self) -> bool: ...
    @property
    def indexed_by_normal(self) -> bool: ...
    @property
    def eye_space(self) -> bool: ...
    @property
    def pixels(self) -> Optional[npt.NDArray[np.float32]]:
        """(H, W, 4) float32 RGBA, read-only, row 0 at the top; a view without a copy for maps."""
    @property
    def result(self) -> Optional[dict[str, Any]]:
        """prefilter()'s entry for the map (as `brdfbake prefilter --json`), else None."""
    def describe(self) -> dict[str, Any]: ...
    def sample(self, dirs: Optional[_Directions] = None, cos_view: Optional[float] = None) -> npt.NDArray[np.float64]:
        """(N, 4) RGBA lookups at (N, 3) directions ((4,) for one (3,) direction), as `brdfbake sample`."""
    @property
    def levels(self) -> list[npt.NDArray[np.float32]]:
        """Every mip level (a map in memory), or [pixels]."""
    def save(
        self,
        path: _Path,
        more: Sequence[_Path] = ...,
        *,
        texel_format: Optional[str] = None,
        faces: bool = False,
        tiled: bool = False,
    ) -> list[pathlib.Path]:
        """Writes a map made in memory; returns every file written."""

class Ibl:
    """Engine-ready image-based lighting in memory (cube maps as (6, N, N, 4) arrays)."""

    @property
    def specular(self) -> list[npt.NDArray[np.float32]]: ...
    @property
    def irradiance(self) -> npt.NDArray[np.float32]: ...
    @property
    def sh(self) -> npt.NDArray[np.float64]: ...
    @property
    def skybox(self) -> npt.NDArray[np.float32]: ...
    @property
    def dfg(self) -> npt.NDArray[np.float32]: ...
    def to_json(self) -> dict[str, Any]: ...
    def save(
        self,
        out_dir: _Path,
        *,
        format: str = "ktx2",
        stem: str = "ibl",
        texel_format: Optional[str] = None,
        sh_format: str = "brdfbake",
    ) -> dict[str, Any]: ...

class MapResult:
    """One map of a spec as made."""

    @property
    def json_path(self) -> str: ...
    @property
    def output(self) -> pathlib.Path: ...
    @property
    def written(self) -> bool: ...
    @property
    def error(self) -> str: ...
    @property
    def files(self) -> list[pathlib.Path]: ...
    @property
    def notes(self) -> list[str]: ...
    @property
    def map(self) -> Optional[Map]:
        """The map when the spec named no output for it (made in memory only), else None."""
    def to_json(self) -> dict[str, Any]: ...
    def brief_report(self) -> str: ...

class BakeResult:
    """A spec run: every map's result, in the spec's order."""

    @property
    def spec(self) -> pathlib.Path: ...
    @property
    def maps(self) -> list[MapResult]: ...
    @property
    def files(self) -> list[pathlib.Path]: ...
    @property
    def notes(self) -> list[str]: ...
    @property
    def failed(self) -> int: ...
    @property
    def _first_error(self) -> Optional[tuple[str, str]]: ...
    def to_json(self) -> dict[str, Any]:
        """What `brdfbake bake --json` prints."""
    def brief_report(self) -> str: ...

class Fit:
    """Lobes fitted to a measured table, with the fit's statistics and held-out error."""

    @property
    def table(self) -> pathlib.Path: ...
    @property
    def samples(self) -> int: ...
    @property
    def files(self) -> list[pathlib.Path]: ...
    @property
    def notes(self) -> list[str]: ...
    @property
    def usable(self) -> bool: ...
    @property
    def channel_names(self) -> list[str]: ...
    @property
    def model(self) -> dict[str, Any]: ...
    @property
    def channels(self) -> list[dict[str, Any]]: ...
    @property
    def lobes(self) -> list[list[dict[str, Any]]]: ...
    @property
    def held_out(self) -> Optional[dict[str, Any]]: ...
    @property
    def held_out_score(self) -> Optional[float]: ...
    @property
    def in_sample_error(self) -> float: ...
    @property
    def candidates(self) -> Optional[list[dict[str, Any]]]: ...
    @property
    def seconds(self) -> float: ...
    @property
    def document(self) -> dict[str, Any]:
        """The fit.json document save() writes."""
    def evaluate(self, wi: _Directions, wo: _Directions) -> npt.NDArray[np.float64]:
        """(N, C) BRDF values (1/sr) for (N, 3) lights and views, as `brdfbake eval`."""
    def save(self, path: _Path) -> None:
        """Writes fit.json, as `brdfbake fit -o PATH`."""
    def to_json(self) -> dict[str, Any]:
        """What `brdfbake fit --json` prints."""
    def brief_report(self) -> str: ...

def read_map(path: _Path, *, from_: Optional[str] = None, mip_level: int = 0) -> Map:
    """Reads any output of bake or prefilter."""

def run_spec(
    spec: Optional[_Path],
    document: Optional[Any],
    out_dir: Optional[_Path],
    threads: int,
    allow_large: bool,
    label: str,
    progress: _Progress,
) -> BakeResult: ...
def fit_table(
    table: _Path,
    lobes: Union[int, str],
    kind: str,
    elevation: str,
    method: str,
    max_exponent: Union[float, str],
    varying_prior: Union[float, str],
    color_profile: str,
    half_difference: str,
    held_out: bool,
    folds: int,
    channels: str,
    rgb: str,
    format: str,
    output: Optional[_Path],
    report: Optional[_Path],
    threads: int,
    progress: _Progress,
) -> Fit: ...
def prefilter(
    environment: Environment,
    lobe: str,
    to: str,
    resolution: int,
    output: Optional[_Path],
    method: str,
    max_error: float,
    from_: Optional[str],
    mips: bool,
    tiled: bool,
    faces: bool,
    view: Optional[Sequence[float]],
    up: Optional[Sequence[float]],
    samples_per_texel: int,
    elevations: Optional[int],
    fresnel_ior: Optional[float],
    combine: Optional[str],
    chain: Optional[str],
    gloss_scale: Optional[float],
    gloss_bias: Optional[float],
    mip_count: Optional[int],
    edge_fixup: bool,
    sh_output: Optional[_Path],
    threads: int,
    progress: _Progress,
) -> Map: ...
def matcap(
    material: Union[_Path, dict[str, Any], Fit],
    environment: Environment,
    resolution: int,
    max_error: float,
    max_relative_error: Optional[float],
    method: str,
    camera: Optional[Sequence[float]],
    parameterization: str,
    samples_per_texel: int,
    exposure: float,
    output: Optional[_Path],
    threads: int,
    progress: _Progress,
) -> Map: ...
def ibl(
    environment: Environment,
    resolution: int,
    irradiance_resolution: int,
    skybox_resolution: int,
    dfg_size: int,
    dfg_form: str,
    max_error: float,
    threads: int,
    progress: _Progress,
) -> Ibl: ...
