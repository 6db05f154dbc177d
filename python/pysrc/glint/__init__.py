"""glint: a Whitted ray tracer whose Vulkan renders are checked against a
CPU reference, from Python (docs/python.md).

    >>> import glint
    >>> scene = glint.load("scenes/seed-fig4.toml", width=64, height=48)
    >>> image = glint.render(scene)              # numpy float32, (48, 64, 3)
    >>> result = glint.compare(scene)            # GPU f32 against CPU f64
    >>> result.passed
    True
    >>> glint.explain(scene, (32, 24))[0].agree  # one pixel's ray trees side by side
    True

Images are numpy ``float32`` arrays of shape ``(height, width, 3)`` in
linear RGB. Every error is a :class:`glint.Error`; its message is the line
the ``glint`` binary prints for the same error.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Iterable, Iterator, List, Literal, Mapping, MutableMapping, Optional, Sequence, Tuple, Union, cast, overload

import numpy as np
import numpy.typing as npt

from . import _glint
from ._glint import (
    DeviceError,
    Error,
    ImageError,
    Scene,
    SceneError,
    ShaderError,
)

__all__ = [
    "load",
    "loads",
    "render",
    "diff",
    "compare",
    "explain",
    "read",
    "write",
    "devices",
    "show",
    "Shown",
    "Scene",
    "Params",
    "Aovs",
    "Renderer",
    "PreparedScene",
    "Figures",
    "Comparison",
    "Explanation",
    "Error",
    "SceneError",
    "ShaderError",
    "DeviceError",
    "ImageError",
    "GPU_BUILT",
]

#: Whether this build has the GPU renderer (a CPU-only build raises
#: DeviceError from every GPU call).
GPU_BUILT: bool = _glint.GPU_BUILT

PathLike = Union[str, "os.PathLike[str]"]
Region = Tuple[int, int, int, int]
Include = Union[PathLike, Sequence[PathLike], Mapping[str, str]]
#: An image: float32, (height, width, 3), linear RGB.
Image = npt.NDArray[np.float32]
#: A render's ray counts and times (``stats=True``).
Stats = Dict[str, Any]
#: A render's ``progress=``: called as ``progress(pixels_done, pixels)``
#: on the calling thread while the render runs, and once at its end.
Progress = Callable[[int, int], object]


def load(
    path: PathLike,
    width: Optional[int] = None,
    height: Optional[int] = None,
    samples: Optional[int] = None,
    max_depth: Optional[int] = None,
) -> Scene:
    """Reads a scene file: TOML or NFF (docs/scene-format.md), or an OBJ
    mesh, which gets a camera that frames it and two lights (docs/python.md).
    The keywords override the file as ``glint render --width`` and the
    others do. Raises :class:`SceneError` with ``.file``, ``.line`` and
    ``.column``."""
    return _glint.load(os.fspath(path), width, height, samples, max_depth)


def loads(
    text: str,
    format: str = "toml",
    width: Optional[int] = None,
    height: Optional[int] = None,
    samples: Optional[int] = None,
    max_depth: Optional[int] = None,
) -> Scene:
    """As :func:`load`, from a string: ``format`` is ``"toml"`` or
    ``"nff"``. Files the text names (meshes, textures) are relative to the
    working directory."""
    return _glint.loads(text, format, width, height, samples, max_depth)


class Params(MutableMapping[str, Any]):
    """A scene's values by their keys in its file: ``scene.params``.

    Keys are paths into the scene file's tables, as an error names them:
    ``"spheres[0].center"``, ``"materials.red.diffuse"``,
    ``"lights[1].position"``, ``"camera.eye"`` (a name with a dot, a
    space or a quote in double quotes, with ``\\"`` and ``\\\\`` escaped as
    TOML writes them: ``'materials."red glass".diffuse'``).
    Iterating lists every number and list of numbers of the file but the
    image's settings and ``render.max_depth``; any key of the file can be
    read and set, and a table's missing key (a material's ``specular``)
    can be given. A key naming an entry the scene does not have (a
    misspelt material) is a KeyError; :meth:`add` makes new entries.
    ``del params[key]`` takes a key back to its default.

    Setting a value reads the scene again, whole, with every check a file
    gets (its meshes' OBJ files are not read again while unchanged: their
    length and time of change say so); a bad value raises and changes
    nothing. ``update`` sets many at one reading. A render then shows the
    change: a renderer's ``render`` of the same scene, and a
    :class:`PreparedScene` of it, write the new values over the ones on
    the device and refit the BVH, compiling nothing; where the change
    needs another shader variant (a deeper ray tree, a new kind of
    object or light) the scene is prepared again, its stats say
    ``"compiled": True``, and the ``glint`` logger records why at INFO.
    """

    def __init__(self, scene: Scene) -> None:
        self._scene = scene

    def __getitem__(self, key: str) -> Any:
        return self._scene._param(key)

    def __setitem__(self, key: str, value: Any) -> None:
        self._scene._set_params({key: value})

    def __delitem__(self, key: str) -> None:
        self._scene._set_params({key: None})

    def __iter__(self) -> Iterator[str]:
        return iter(self._scene._params())

    def __len__(self) -> int:
        return len(self._scene._params())

    def update(self, *others: Any, **values: Any) -> None:
        """Sets every key given (a mapping, pairs, or keywords) at one
        reading of the scene: all of them, or none on an error."""
        items: Dict[str, Any] = {}
        for other in others:
            pairs: Iterable[Tuple[str, Any]] = other.items() if isinstance(other, Mapping) else other
            items.update(pairs)
        items.update(values)
        self._scene._set_params(items)

    def add(self, key: str, value: Any) -> None:
        """Sets ``key`` as ``params[key] = value`` does, making the
        entries on its way that the scene does not have: ``add("materials.
        blue.diffuse", [0, 0, 1])`` makes the material ``blue``. An
        array's entry is never made (``to_dict`` and ``from_dict`` can)."""
        self._scene._set_params({key: value}, True)

    def __repr__(self) -> str:
        return f"<glint.Params of {self._scene.source!r}: {dict(self)!r}>"


def _include(include: Optional[Include]) -> Any:
    if include is None or isinstance(include, Mapping):
        return None if include is None else dict(include)
    if isinstance(include, (str, os.PathLike)):
        return os.fspath(include)
    return [os.fspath(d) for d in include]


#: A render's AOVs (``aovs=[...]``): ``"color"`` and each AOV asked for,
#: by name (docs/python.md, AOVs).
Aovs = Dict[str, npt.NDArray[Any]]


def _result(
    image: Image, raw: Optional[str], stats: bool, aovs: Optional[Dict[str, Any]] = None,
    asked: bool = False,
) -> Any:
    # `aovs=[]` asks for the dict too, with the colour alone in it.
    out: Union[Image, Aovs] = image if aovs is None and not asked else {"color": image, **(aovs or {})}
    if not stats:
        return out
    assert raw is not None, "a render asked for stats returns them"
    return out, cast(Stats, json.loads(raw))


def _overridden(
    scene: Scene, width: Optional[int], height: Optional[int], samples: Optional[int], max_depth: Optional[int]
) -> Scene:
    if width is None and height is None and samples is None and max_depth is None:
        return scene
    return scene._overridden(width, height, samples, max_depth)


def _progress(progress: Any) -> Optional[Progress]:
    """``progress`` as glint calls it, ``(pixels_done, pixels)``. A tqdm
    bar (anything with ``update`` and ``total``), or its ``update`` method,
    takes increments instead: the bar's total is set to the pixels and it
    is moved by what was done since its last call (``progress=bar.update``
    raised TypeError, glint passing two numbers to a one-number method)."""
    if progress is None:
        return None
    bar = progress
    if getattr(progress, "__name__", None) == "update" and hasattr(progress, "__self__"):
        bar = progress.__self__
    if not (hasattr(bar, "update") and hasattr(bar, "total")):
        if not callable(progress):
            raise TypeError(f"progress={progress!r}: a callable progress(done, total), or a tqdm bar")
        return cast(Progress, progress)
    shown = [0]

    def moved(done: int, total: int) -> None:
        if bar.total != total:
            bar.total = total
            refresh = getattr(bar, "refresh", None)
            if callable(refresh):
                refresh()
        if done > shown[0]:
            bar.update(done - shown[0])
            shown[0] = done

    return moved


def _aovs(aovs: Optional[Sequence[str]]) -> Optional[List[str]]:
    if aovs is None:
        return None
    if isinstance(aovs, str):
        raise TypeError(f"aovs={aovs!r}: a list of names, such as [{aovs!r}]")
    return list(aovs)


class PreparedScene:
    """A scene laid out, compiled and uploaded for one device: each
    :meth:`render` only traces. Made by :meth:`Renderer.prepare`. It
    follows its scene: a render after a change of ``scene.params`` shows
    it (in place, or prepared again where the change needs another
    shader; :class:`Params`)."""

    def __init__(self, native: _glint.PreparedScene) -> None:
        self._native = native

    @overload
    def render(
        self, region: Optional[Region] = None, stats: Literal[False] = False,
        progress: Optional[Progress] = None,
    ) -> Image: ...
    @overload
    def render(
        self, region: Optional[Region] = None, *, stats: Literal[True],
        progress: Optional[Progress] = None,
    ) -> Tuple[Image, Stats]: ...
    @overload
    def render(
        self, region: Optional[Region], stats: Literal[True], progress: Optional[Progress] = None,
    ) -> Tuple[Image, Stats]: ...

    def render(
        self, region: Optional[Region] = None, stats: bool = False,
        progress: Optional[Progress] = None,
    ) -> Union[Image, Tuple[Image, Stats]]:
        """The image, or the region ``(x, y, width, height)`` of it (its
        pixels are bit for bit those of the whole image). With
        ``stats=True``, ``(image, stats)``: the times, and the ray counts
        where the scene was prepared with ``stats=True``. ``progress`` is
        called as ``progress(pixels_done, pixels)`` as tiles finish."""
        image, raw, _ = self._native.render(_region(region), stats, _progress(progress))
        return cast(Union[Image, Tuple[Image, Stats]], _result(image, raw, stats))

    @property
    def size(self) -> Tuple[int, int]:
        """(width, height) of the image."""
        return self._native.size

    def __repr__(self) -> str:
        return repr(self._native)


class Renderer:
    """A Vulkan device, opened once, and the shaders compiled on it, kept
    across calls. ``device`` picks one by a part of its name (see
    :func:`devices`); lavapipe, Vulkan on the CPU, where there is no GPU.

    ``include`` is a folder, a list of folders searched before the
    built-in shader files (as ``glint render -I DIR``), or a dict of file
    name to GLSL text. ``defines`` are ``-D`` defines (name to value or
    None). ``validate`` turns the Khronos validation layer on (default: the
    environment's GLINT_VALIDATION=1). ``timeout`` is the longest wait for
    one tile, in seconds (default: glint's own bound from the tile's work).
    ``cache=False`` keeps compiled SPIR-V and pipelines out of the cache
    the binary shares (``~/.cache/glint``), as ``--no-cache`` does.
    """

    def __init__(
        self,
        device: Optional[str] = None,
        *,
        include: Optional[Include] = None,
        defines: Optional[Mapping[str, Optional[str]]] = None,
        validate: Optional[bool] = None,
        timeout: Optional[float] = None,
        cache: bool = True,
    ) -> None:
        self._native = _glint.Renderer(
            device,
            _include(include),
            None if defines is None else dict(defines),
            validate,
            timeout,
            cache,
        )

    @property
    def device(self) -> str:
        """The device's name."""
        return self._native.device

    def prepare(
        self, scene: Scene, precision: str = "f32", stats: bool = False
    ) -> PreparedScene:
        """Lays ``scene`` out for the device, compiles its shader variant
        (once per variant and renderer) and uploads it. ``stats=True``
        compiles the counting variant, whose renders also count rays."""
        return PreparedScene(self._native.prepare(scene, precision, stats))

    @overload
    def render(
        self, scene: Scene, precision: str = "f32", region: Optional[Region] = None,
        stats: Literal[False] = False, progress: Optional[Progress] = None, aovs: None = None,
    width: Optional[int] = None, height: Optional[int] = None,
    samples: Optional[int] = None, max_depth: Optional[int] = None,
    ) -> Image: ...
    @overload
    def render(
        self, scene: Scene, precision: str = "f32", region: Optional[Region] = None,
        *, stats: Literal[True], progress: Optional[Progress] = None, aovs: None = None,
    width: Optional[int] = None, height: Optional[int] = None,
    samples: Optional[int] = None, max_depth: Optional[int] = None,
    ) -> Tuple[Image, Stats]: ...
    @overload
    def render(
        self, scene: Scene, precision: str = "f32", region: Optional[Region] = None,
        stats: Literal[False] = False, progress: Optional[Progress] = None, *, aovs: Sequence[str],
    width: Optional[int] = None, height: Optional[int] = None,
    samples: Optional[int] = None, max_depth: Optional[int] = None,
    ) -> Aovs: ...
    @overload
    def render(
        self, scene: Scene, precision: str = "f32", region: Optional[Region] = None,
        *, stats: Literal[True], progress: Optional[Progress] = None, aovs: Sequence[str],
    width: Optional[int] = None, height: Optional[int] = None,
    samples: Optional[int] = None, max_depth: Optional[int] = None,
    ) -> Tuple[Aovs, Stats]: ...

    def render(
        self,
        scene: Scene,
        precision: str = "f32",
        region: Optional[Region] = None,
        stats: bool = False,
        progress: Optional[Progress] = None,
        aovs: Optional[Sequence[str]] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        samples: Optional[int] = None,
        max_depth: Optional[int] = None,
    ) -> Union[Image, Tuple[Image, Stats], Aovs, Tuple[Aovs, Stats]]:
        """The image, or ``(image, stats)``; with ``aovs``, a dict of the
        image (``"color"``) and the AOVs named (docs/python.md, AOVs) in
        place of the image. The renderer keeps the scene it rendered last
        prepared (its buffers on the device) while it is given that scene
        again, with the same precision, stats and AOVs: a repeat render
        only traces, and one after a change of ``scene.params`` updates it
        in place (:class:`Params`). ``width``, ``height``, ``samples`` and
        ``max_depth`` render it as :func:`load` would have read it with
        them, the scene unchanged."""
        image, raw, values = self._native.render(
            _overridden(scene, width, height, samples, max_depth), precision, _region(region), stats, _progress(progress), _aovs(aovs)
        )
        return cast(
            Union[Image, Tuple[Image, Stats], Aovs, Tuple[Aovs, Stats]],
            _result(image, raw, stats, values, aovs is not None),
        )

    def explain(
        self, scene: Scene, pixel: Tuple[int, int], sample: Optional[int] = None
    ) -> List["Explanation"]:
        """``glint explain``: pixel ``(x, y)``'s ray tree on this device and
        on the CPU in f32 and f64, one :class:`Explanation` a sample (``sample``:
        that one alone)."""
        raw = self._native.explain(scene, _pixel(pixel), sample)
        return [Explanation._from(e) for e in json.loads(raw)]

    def __repr__(self) -> str:
        return repr(self._native)


@dataclass(frozen=True)
class Explanation:
    """One sample of a pixel explained (``glint explain``; docs/guide.md,
    Why does this pixel differ?). ``str()`` is the table and the verdict
    the binary prints."""

    #: ``pixel`` (x, y), ``index`` among the pixel's samples, and ``traced``
    #: (x, y, i, j of the image the renderers trace).
    sample: Dict[str, Any]
    #: Whether the GPU's tree stays within every quantity's f32 bound, and
    #: the pixel the render wrote is its recorded samples' mean.
    agree: bool
    #: The GPU's first divergence (quantity, stage, value, reference,
    #: difference, bound, ill_conditioned, cause), or None.
    divergence: Optional[Dict[str, Any]]
    #: The trees: the GPU's, the CPU's f32, the CPU's f64 (the reference);
    #: each ray with ``origin``, ``direction`` and the rest by name.
    trees: List[Dict[str, Any]]
    #: The table, one block per ray and one column per renderer.
    table: str
    #: The verdict in words.
    verdict: str
    #: Where the pixel the plain render wrote is not the mean of its
    #: recorded samples: what it wrote and what they say; else None.
    render: Optional[str] = None

    @classmethod
    def _from(cls, d: Mapping[str, Any]) -> "Explanation":
        e = d["explanation"]
        return cls(
            sample=e["sample"],
            agree=e["agree"],
            divergence=e["divergences"][0],
            trees=e["trees"],
            table=d["table"],
            verdict=d["verdict"],
            render=e.get("render"),
        )

    def __str__(self) -> str:
        return f"{self.table}\n{self.verdict}"


_default: Optional[Renderer] = None


def _default_renderer() -> Renderer:
    global _default
    if _default is None:
        _default = Renderer()
    return _default


@overload
def render(
    scene: Scene, backend: str = "gpu", precision: str = "f32", region: Optional[Region] = None,
    stats: Literal[False] = False, renderer: Optional[Renderer] = None,
    progress: Optional[Progress] = None, aovs: None = None,
    width: Optional[int] = None, height: Optional[int] = None,
    samples: Optional[int] = None, max_depth: Optional[int] = None,
) -> Image: ...
@overload
def render(
    scene: Scene, backend: str = "gpu", precision: str = "f32", region: Optional[Region] = None,
    *, stats: Literal[True], renderer: Optional[Renderer] = None,
    progress: Optional[Progress] = None, aovs: None = None,
    width: Optional[int] = None, height: Optional[int] = None,
    samples: Optional[int] = None, max_depth: Optional[int] = None,
) -> Tuple[Image, Stats]: ...
@overload
def render(
    scene: Scene, backend: str = "gpu", precision: str = "f32", region: Optional[Region] = None,
    stats: Literal[False] = False, renderer: Optional[Renderer] = None,
    progress: Optional[Progress] = None, *, aovs: Sequence[str],
    width: Optional[int] = None, height: Optional[int] = None,
    samples: Optional[int] = None, max_depth: Optional[int] = None,
) -> Aovs: ...
@overload
def render(
    scene: Scene, backend: str = "gpu", precision: str = "f32", region: Optional[Region] = None,
    *, stats: Literal[True], renderer: Optional[Renderer] = None,
    progress: Optional[Progress] = None, aovs: Sequence[str],
    width: Optional[int] = None, height: Optional[int] = None,
    samples: Optional[int] = None, max_depth: Optional[int] = None,
) -> Tuple[Aovs, Stats]: ...


def render(
    scene: Scene,
    backend: str = "gpu",
    precision: str = "f32",
    region: Optional[Region] = None,
    stats: bool = False,
    renderer: Optional[Renderer] = None,
    progress: Optional[Progress] = None,
    aovs: Optional[Sequence[str]] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    samples: Optional[int] = None,
    max_depth: Optional[int] = None,
) -> Union[Image, Tuple[Image, Stats], Aovs, Tuple[Aovs, Stats]]:
    """Renders ``scene``: on the GPU through ``renderer`` (a default one,
    opened at the first call, where None), or with the CPU reference
    (``backend="cpu"``), in ``"f32"`` or ``"f64"``. Returns the image, or
    ``(image, stats)`` with ``stats=True`` (ray counts and times, as
    ``glint render --stats`` writes them). ``progress`` is called as
    ``progress(pixels_done, pixels)`` while the render runs (GPU tiles or
    CPU rows), and once at its end: a tqdm bar's ``update``, say.

    ``aovs`` names AOVs of the eye ray's first hit: ``"depth"``,
    ``"normal"``, ``"albedo"``, ``"prim_id"``, and ``"rays"``, the rays
    each pixel traced. With it, the image is a dict of ``"color"`` and
    those arrays (docs/python.md, AOVs).

    ``width``, ``height``, ``samples`` and ``max_depth`` render the scene
    as :func:`load` would have read it with them (another size or sample
    count without a reload); the scene itself is unchanged."""
    scene = _overridden(scene, width, height, samples, max_depth)
    if backend == "gpu":
        r = renderer if renderer is not None else _default_renderer()
        image, raw, values = r._native.render(
            scene, precision, _region(region), stats, _progress(progress), _aovs(aovs)
        )
    elif backend == "cpu":
        image, raw, values = _glint.render_cpu(
            scene, precision, _region(region), stats, _progress(progress), _aovs(aovs)
        )
    else:
        raise ValueError(f'backend {backend!r}: glint renders with "gpu" or "cpu"')
    return cast(
        Union[Image, Tuple[Image, Stats], Aovs, Tuple[Aovs, Stats]],
        _result(image, raw, stats, values, aovs is not None),
    )


@dataclass(frozen=True)
class Figures:
    """An image's error against a reference (docs/commands.md), over linear
    values: the largest channel error, the RMSE, the PSNR for a peak of 1,
    the share of pixels off by more than 1/255, and the channel pairs that
    are not finite."""

    max_abs: float
    rmse: float
    psnr_db: float
    frac_over_1_255: float
    nonfinite: int

    @classmethod
    def _from(cls, d: Mapping[str, Any]) -> "Figures":
        psnr = d["psnr_db"]
        if psnr is None:  # JSON has no infinities: +inf where equal
            psnr = math.inf if d["nonfinite"] == 0 else -math.inf
        return cls(d["max_abs"], d["rmse"], psnr, d["frac_over_1_255"], d["nonfinite"])


def _whole_numbers(value: Any, count: int, what: str) -> Tuple[int, ...]:
    """``value`` as ``count`` whole numbers >= 0, else ValueError: a float
    is not cut to an int, nor a third number dropped."""
    try:
        items = list(value)
    except TypeError:
        raise ValueError(f"{what}: {value!r} is not {count} whole numbers") from None
    ok = len(items) == count and all(
        isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_)) and v >= 0
        for v in items
    )
    if not ok:
        raise ValueError(f"{what}: {value!r} is not {count} whole numbers >= 0")
    return tuple(int(v) for v in items)


def _region(region: Any) -> Optional[Tuple[int, int, int, int]]:
    if region is None:
        return None
    x, y, w, h = _whole_numbers(region, 4, "region (x, y, width, height)")
    return (x, y, w, h)


def _pixel(pixel: Any) -> Tuple[int, int]:
    x, y = _whole_numbers(pixel, 2, "pixel (x, y)")
    return (x, y)


def _srgb_decode(levels: npt.NDArray[Any], top: int) -> Image:
    # IEC 61966-2-1 as glint.read decodes a PNG: level / top in float32,
    # the curve in float64, rounded once to float32.
    c = (np.asarray(levels, dtype=np.float32) / np.float32(top)).astype(np.float64)
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return cast(Image, linear.astype(np.float32))


def _image(a: Any, what: str) -> Image:
    # An 8- or 16-bit array holds sRGB display levels, as a PNG does: 255
    # (65535) is 1.0 and 128 is 0.216 linear, so that writing it as a PNG
    # gives those levels back (a uint8 image of 128s was written white;
    # one convention for PNG levels). Other integers and bools say nothing
    # of a scale: refused.
    kind = np.asarray(a).dtype
    if kind == np.uint8 or kind == np.uint16:
        a = _srgb_decode(np.asarray(a), int(np.iinfo(kind).max))
    elif kind == np.bool_ or np.issubdtype(kind, np.integer):
        raise ValueError(
            f"{what}: a {kind} array; an image is floats (linear, 1.0 white), or uint8 or uint16 sRGB levels"
        )
    image: Image = np.ascontiguousarray(a, dtype=np.float32)
    if image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"{what}: shape {image.shape}; an image is (height, width, 3)")
    return image


def diff(a: Any, b: Any) -> Figures:
    """The error figures of image ``a`` against the reference ``b``."""
    return Figures._from(json.loads(_glint.diff_json(_image(a, "a"), _image(b, "b"))))


@dataclass(frozen=True)
class Comparison:
    """What :func:`compare` found (``glint compare``'s check)."""

    #: Whether the image is within the tolerance.
    passed: bool
    #: Over every pixel, in units of ``unit``.
    error: Figures
    #: Over the well-conditioned pixels, where the whole image failed.
    well_conditioned: Optional[Figures]
    #: The share of pixels ill-conditioned at f32 (None: not needed).
    ill_share: Optional[float]
    #: How the image breaks the tolerance; empty when it passes.
    violations: List[str]
    #: The pixels off by more than 1/255 of ``unit``: bool, (height, width).
    over: npt.NDArray[np.bool_]
    #: The ill-conditioned pixels, where the check needed them.
    ill: Optional[npt.NDArray[np.bool_]]
    #: The image checked and the CPU f64 reference.
    image: Image
    reference: Image
    #: 1, or the reference's peak where it is above 1.
    unit: float
    #: The tolerance held to: ``frac_over_1_255`` and ``rmse``.
    tolerance: Dict[str, float] = field(default_factory=dict)

    @property
    def failing(self) -> npt.NDArray[np.bool_]:
        """The pixels that count against the image: over 1/255 and, where
        the check left the ill-conditioned out, well-conditioned."""
        return self.over if self.ill is None else self.over & ~self.ill

    def _repr_png_(self) -> bytes:
        """The image, the reference and the failing pixels (red on black)
        side by side, as Jupyter shows a comparison."""
        mask = np.zeros_like(self.reference)
        mask[self.failing] = (1.0, 0.0, 0.0)
        return show(self.image, self.reference, mask)._repr_png_()


def compare(
    scene: Scene,
    image: Optional[Any] = None,
    *,
    backend: str = "gpu",
    renderer: Optional[Renderer] = None,
    frac_over_1_255: Optional[float] = None,
    rmse: Optional[float] = None,
) -> Comparison:
    """``glint compare``'s check: an f32 render of ``scene`` (on the GPU, or
    the CPU's f32 with ``backend="cpu"``; or ``image``, given) against the
    CPU f64 reference, with the tolerance (default: 0.1 % of pixels over
    1/255, RMSE 4e-3) over every pixel and, where that fails, over the
    pixels well-conditioned at f32 (docs/guide.md, Accuracy)."""
    if image is None:
        image = render(scene, backend=backend, precision="f32", renderer=renderer)
    checked, reference, raw, over, ill = _glint.compare_raw(
        scene, _image(image, "image"), frac_over_1_255, rmse
    )
    j = json.loads(raw)
    c = j["conditioned"]
    return Comparison(
        passed=j["passed"],
        error=Figures._from(j["error"]),
        well_conditioned=None if c is None else Figures._from(c["error"]),
        ill_share=None if c is None else c["ill"],
        violations=j["violations"],
        over=over,
        ill=ill,
        image=checked,
        reference=reference,
        unit=j["unit"],
        tolerance=j["tolerance"],
    )


def explain(
    scene: Scene,
    pixel: Tuple[int, int],
    *,
    sample: Optional[int] = None,
    renderer: Optional[Renderer] = None,
) -> List[Explanation]:
    """``glint explain``: pixel ``(x, y)``'s ray tree on the GPU (``renderer``,
    or the default one) and on the CPU in f32 and f64, down to the first
    number that differs and its cause; one :class:`Explanation` a sample.
    A pixel outside the image or a sample past the pixel's raises
    ValueError; an adaptively sampled scene, glint.Error."""
    return (renderer or _default_renderer()).explain(scene, pixel, sample)


def read(path: PathLike, srgb: bool = True) -> Image:
    """A PNG, PFM or EXR file as a linear image. A PNG is sRGB-encoded, and
    its levels are decoded (``srgb=False``: read as level/255); PFM and EXR
    are linear as stored (docs/scene-format.md, Colour). A one-channel PFM
    or EXR (a depth :func:`write` wrote) is a ``(height, width)`` array."""
    return _glint.read(os.fspath(path), srgb)


def write(image: Any, path: PathLike, srgb: bool = True) -> None:
    """Writes a linear image as PNG, PFM or EXR, by the extension, at once
    (a temporary file renamed into place): a failed write leaves no file.
    A PNG is sRGB-encoded before its 8-bit quantization (``srgb=False``:
    linear levels), so it looks as the image should and :func:`read`
    gives it back; PFM and EXR hold the values as they are. A ``(height,
    width)`` array (an AOV's depth or ray counts) is written as a PFM or
    EXR of one channel, its values as they are (``inf`` too)."""
    a = np.asarray(image)
    if a.ndim == 2:
        if a.dtype == np.bool_ or not (np.issubdtype(a.dtype, np.number)):
            raise ValueError(f"image: a {a.dtype} array; a one-channel image is numbers")
        _glint.write_plane(np.ascontiguousarray(a, dtype=np.float32), os.fspath(path))
        return
    _glint.write(_image(image, "image"), os.fspath(path), srgb)


class Shown:
    """Images as a notebook shows them (:func:`show`): ``_repr_png_`` is
    their PNG, side by side with a gap between, clamped to [0, 1] and
    sRGB-encoded as :func:`write` writes a PNG."""

    def __init__(self, images: Sequence[Image]) -> None:
        self.images = list(images)

    def _repr_png_(self) -> bytes:
        height = max(i.shape[0] for i in self.images)
        gap = np.ones((height, 4, 3), dtype=np.float32)
        row: List[Image] = []
        for i, image in enumerate(self.images):
            if i:
                row.append(gap)
            pad = np.zeros((height, image.shape[1], 3), dtype=np.float32)
            pad[: image.shape[0]] = np.nan_to_num(image, nan=0.0, posinf=1.0, neginf=0.0)
            row.append(pad)
        import tempfile

        with tempfile.TemporaryDirectory(prefix="glint-show-") as d:
            path = os.path.join(d, "shown.png")
            write(np.concatenate(row, axis=1), path)
            with open(path, "rb") as f:
                return f.read()

    def __repr__(self) -> str:
        sizes = ", ".join(f"{i.shape[1]}x{i.shape[0]}" for i in self.images)
        return f"<glint.Shown {sizes}>"


def show(*images: Any) -> Shown:
    """One or more images to show inline in Jupyter (``_repr_png_``):
    ``glint.show(glint.render(scene))``, or several side by side."""
    if not images:
        raise ValueError("show: give at least one image")
    return Shown([_grey(a) if np.ndim(a) == 2 else _image(a, f"image {i}") for i, a in enumerate(images)])


def _grey(a: Any) -> Image:
    # A (height, width) array (an AOV's depth, its rays) as grey: its
    # finite values from their least (black) to their greatest (white),
    # the rest (a depth's inf where nothing was met) black.
    v = np.asarray(a, dtype=np.float64)
    finite = np.isfinite(v)
    lo, hi = (float(v[finite].min()), float(v[finite].max())) if finite.any() else (0.0, 1.0)
    scaled = np.where(finite, (v - lo) / (hi - lo) if hi > lo else np.clip(v, 0.0, 1.0), 0.0)
    return cast(Image, np.repeat(scaled[:, :, None], 3, axis=2).astype(np.float32))


def devices() -> List[Dict[str, Any]]:
    """The Vulkan devices, best (the default) first: name, type, driver and
    what glint reads of them (``glint info --json``); ``[]`` where there is
    no Vulkan driver or loader (render with ``backend="cpu"`` then)."""
    return cast(List[Dict[str, Any]], json.loads(_glint.devices_json()))
