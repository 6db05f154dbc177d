# Types of the Rust extension glint._glint (python/src/). The public API is
# pysrc/glint/__init__.py, which wraps these; this file lets a type checker follow
# it through.

import os
from typing import Any, Callable, Dict, List, Mapping, MutableMapping, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "DeviceError",
    "Error",
    "GPU_BUILT",
    "ImageError",
    "PreparedScene",
    "Renderer",
    "Scene",
    "SceneError",
    "ShaderError",
    "_test_panic",
    "compare_raw",
    "devices_json",
    "diff_json",
    "load",
    "loads",
    "read",
    "render_cpu",
    "write",
    "write_plane",
]

GPU_BUILT: bool

class Error(Exception): ...

class SceneError(Error):
    file: Optional[str]
    line: Optional[int]
    column: Optional[int]

class ShaderError(Error):
    log: str

class DeviceError(Error): ...
class ImageError(Error): ...

_Image = npt.NDArray[np.float32]
_Mask = npt.NDArray[np.bool_]
_Region = Tuple[int, int, int, int]
_Progress = Callable[[int, int], object]

@final
class Scene:
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def samples(self) -> int: ...
    @property
    def max_depth(self) -> int: ...
    @property
    def counts(self) -> Dict[str, int]: ...
    @property
    def lights(self) -> List[str]: ...
    @property
    def source(self) -> str: ...
    @property
    def base(self) -> str: ...
    @property
    def params(self) -> MutableMapping[str, Any]: ...
    @property
    def generation(self) -> int: ...
    def _params(self) -> Dict[str, Any]: ...
    def _param(self, key: str) -> Any: ...
    def _set_params(self, items: Dict[str, Any], create: bool = False) -> None: ...
    def _overridden(
        self, width: Optional[int] = None, height: Optional[int] = None,
        samples: Optional[int] = None, max_depth: Optional[int] = None,
    ) -> "Scene": ...
    def to_dict(self) -> Dict[str, Any]: ...
    @staticmethod
    def from_dict(
        d: Mapping[str, object],
        base: Optional[Union[str, "os.PathLike[str]"]] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        samples: Optional[int] = None,
        max_depth: Optional[int] = None,
    ) -> "Scene": ...

@final
class PreparedScene:
    def render(
        self,
        region: Optional[_Region] = None,
        stats: bool = False,
        progress: Optional[_Progress] = None,
    ) -> Tuple[_Image, Optional[str], Optional[Dict[str, Any]]]: ...
    @property
    def size(self) -> Tuple[int, int]: ...
    @property
    def counted(self) -> bool: ...

@final
class Renderer:
    def __new__(
        cls,
        device: Optional[str] = None,
        include: Union[None, str, Sequence[str], Mapping[str, str]] = None,
        defines: Optional[Mapping[str, Optional[str]]] = None,
        validate: Optional[bool] = None,
        timeout: Optional[float] = None,
        cache: bool = True,
    ) -> "Renderer": ...
    @property
    def device(self) -> str: ...
    def prepare(self, scene: Scene, precision: str = "f32", stats: bool = False) -> PreparedScene: ...
    def render(
        self,
        scene: Scene,
        precision: str = "f32",
        region: Optional[_Region] = None,
        stats: bool = False,
        progress: Optional[_Progress] = None,
        aovs: Optional[List[str]] = None,
    ) -> Tuple[_Image, Optional[str], Optional[Dict[str, Any]]]: ...
    def explain(self, scene: Scene, pixel: Tuple[int, int], sample: Optional[int] = None) -> str: ...

def load(
    path: str,
    width: Optional[int] = None,
    height: Optional[int] = None,
    samples: Optional[int] = None,
    max_depth: Optional[int] = None,
) -> Scene: ...
def loads(
    text: str,
    format: str = "toml",
    width: Optional[int] = None,
    height: Optional[int] = None,
    samples: Optional[int] = None,
    max_depth: Optional[int] = None,
) -> Scene: ...
def render_cpu(
    scene: Scene,
    precision: str = "f32",
    region: Optional[_Region] = None,
    stats: bool = False,
    progress: Optional[_Progress] = None,
    aovs: Optional[List[str]] = None,
) -> Tuple[_Image, Optional[str], Optional[Dict[str, Any]]]: ...
def devices_json() -> str: ...
def read(path: str, srgb: bool = True) -> npt.NDArray[np.float32]: ...
def write(image: _Image, path: str, srgb: bool = True) -> None: ...
def write_plane(values: npt.NDArray[np.float32], path: str) -> None: ...
def diff_json(a: _Image, b: _Image) -> str: ...
def compare_raw(
    scene: Scene,
    image: _Image,
    frac_over_1_255: Optional[float] = None,
    rmse: Optional[float] = None,
) -> Tuple[_Image, _Image, str, _Mask, Optional[_Mask]]: ...
def _test_panic(on_render_thread: bool) -> None: ...
