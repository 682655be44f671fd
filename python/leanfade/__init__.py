"""leanfade for Python pipelines: bake LEAN maps from NumPy arrays or image files.

    import leanfade
    lean = leanfade.bake("bricks_n.png", bits="16")        # or a (H, W[, C]) NumPy array
    lean.save("bricks_n.ktx2")                              # the bytes `leanfade bake` writes
    lean.levels[0]["lean1"]                                 # (H, W, 4) view, no copy
    leanfade.info("bricks_n.ktx2")["summary"]["mean_slope"]

The settings are `leanfade bake`'s flags with underscores (``from`` is ``from_``); every failure
raises leanfade.Error, whose message is the CLI's one-line error ("<file or setting>: <cause>")
and whose ``subject`` and ``cause`` are its two parts. Bakes, reads and writes release the GIL,
so threads bake in parallel. Batches: ``python3 -m leanfade.batch`` (docs/pipelines.md).
"""
from __future__ import annotations

import os
from typing import Any, Union

from . import _leanfade
from ._leanfade import Cache, Error, LeanMap, __version__, cache_key, default_cache_folder, sha256_file

__all__ = [
    "BAKE_SETTINGS",
    "Cache",
    "Error",
    "LeanMap",
    "__version__",
    "bake",
    "bake_settings",
    "cache_key",
    "default_cache_folder",
    "info",
    "load",
    "roughness_textures",
    "settings_text",
    "sha256_file",
    "write_image",
]

Source = Union[str, "os.PathLike[str]", Any]

# The settings of a bake, with their defaults: `leanfade bake`'s flags (docs/cli.md) without the
# dashes, from the module's table of settings. None for strength: not given (1.0; an error for
# normal maps when given).
BAKE_SETTINGS: dict[str, Any] = dict(_leanfade.BAKE_SETTINGS)


def _setting_error(setting: str, cause: str) -> Error:
    error = Error(f"{setting}: {cause}")
    error.subject, error.cause = setting, cause
    error.kind, error.setting, error.mentioned_settings = "setting", setting, []
    return error


def _normalized(settings: dict[str, Any]) -> dict[str, Any]:
    values = dict(BAKE_SETTINGS)
    for name, value in settings.items():
        key = name.replace("-", "_")
        if key == "from":
            key = "from_"
        if key not in values:
            raise _setting_error(name, "not a bake setting (expected one of "
                         f"{', '.join(sorted(BAKE_SETTINGS))})")
        values[key] = value
    return values


def bake_settings(**settings: Any) -> _leanfade.BakeSettings:
    """The checked settings of a bake (raises leanfade.Error naming the setting)."""
    return _leanfade.BakeSettings(**_normalized(settings))


def settings_text(**settings: Any) -> str:
    """Every bake setting and its value, defaults included, as one canonical line: what a batch
    keys its cache entries by together with the input's bytes."""
    values = _normalized(settings)
    bake_settings(**values)  # checked first
    # threads and max_size change no byte of the result.
    return " ".join(f"{name}={values[name]!r}" for name in sorted(values)
                    if name not in ("threads", "max_size"))


def bake(source: Source, *, name: str = "", **settings: Any) -> LeanMap:
    """Bakes a height or normal map into a LEAN map, as `leanfade bake` does.

    source: an image file (PNG 8/16-bit, OpenEXR, PFM; path or os.PathLike) or a NumPy array of
    shape (H, W) or (H, W, C), C 1-4: uint8 / uint16 are the samples of an 8- / 16-bit file,
    floats are values in [0, 1] (normal maps encoded 0.5 n + 0.5). Rows top first, as in files.
    name: what errors call an array (default "array").
    settings: `leanfade bake`'s flags (from_, strength, strength_unit, sc, directx,
    strict_normals, bits, bake_roughness, plateau_epsilon, wrap, threads, max_size,
    supercompression, zstd_level: how save() and to_bytes() write the KTX2 file).
    """
    return _leanfade.bake(source, bake_settings(**settings), name)


def load(path: Union[str, "os.PathLike[str]"], *, max_size: int = 16384) -> LeanMap:
    """Reads a LEAN map KTX2 file with every check `leanfade info` makes."""
    return _leanfade.load(path, max_size)


def info(path: Union[str, "os.PathLike[str]"]) -> dict[str, Any]:
    """What `leanfade info` reports of a KTX2 file, as a dict: header fields, levels,
    key/values (bytes), and for a LEAN map its storage, scale, plateau layer and moment summary.
    """
    described = _leanfade.inspect(path)
    if described["lean_map"]:
        lean = load(path)
        described.update(storage=lean.storage, encoding=lean.encoding, scale=lean.scale,
                         plateau_epsilon=lean.plateau_epsilon, summary=lean.summary)
    return described


def roughness_textures(source: Source, *, base_roughness: float = 0.0, name: str = "",
                       **settings: Any) -> dict[str, list[Any]]:
    """The engine textures of `leanfade bake --roughness-out` (docs/roughness.md), every MIP
    level as a (h, w, 4) uint8 array: "metallic_roughness" (G = perceptual roughness),
    "normal" (0.5 n + 0.5 of the mean slope) and "anisotropy" (KHR_materials_anisotropy).
    base_roughness: the material's perceptual roughness r0 in [0, 1]."""
    return _leanfade.roughness_textures(source, bake_settings(**settings), base_roughness, name)


def write_image(path: Union[str, "os.PathLike[str]"], array: Any) -> None:
    """Writes a (H, W[, C]) array: uint8 / uint16 as an 8- / 16-bit PNG, floats as OpenEXR
    (.exr) or PFM, atomically."""
    _leanfade.write_image(path, array)
