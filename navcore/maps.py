"""Occupancy grids and the map_server file format (YAML descriptor + PGM/PNG image).

Semantics follow ROS map_server: ``origin`` is the world pose of the lower-left pixel, image row 0
is the top (max-y) edge, so rows are flipped on load. Cell values are the nav_msgs/OccupancyGrid
ones: -1 unknown, 0 free, 100 occupied, 1..99 in ``scale`` mode, the raw grey value in ``raw`` mode.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np
import yaml

from navcore.errors import NavcoreError
from navcore.safe_read import MAX_IMAGE_BYTES, load_yaml_keys, read_bytes
from navcore.types import Pose2D

UNKNOWN = -1
FREE = 0
OCCUPIED = 100

_MODES = ("trinary", "scale", "raw")

# Limits (docs/limits.md): a map of more cells than this is refused before its pixels are decoded
# (4096 x 4096; a PNG of a few kB can claim 2**31 x 2**31 pixels).
MAX_MAP_CELLS = 4096 * 4096
MIN_RESOLUTION = 1e-4   # m per cell
MAX_RESOLUTION = 1e3
MAX_ORIGIN = 1e7        # |origin x, y| in m


class MapError(NavcoreError, ValueError):
    """A map file or descriptor is missing or malformed; the message names the file and field."""


@dataclass(slots=True)
class OccupancyGrid:
    """nav_msgs/OccupancyGrid. ``data`` is (height, width) int16, row 0 at ``origin`` (min y).

    int16 rather than int8 because ``raw`` mode keeps grey values 0..255 unchanged.
    """

    data: np.ndarray
    resolution: float
    origin: Pose2D = Pose2D()
    frame_id: str = "map"

    def __post_init__(self) -> None:
        self.data = np.asarray(self.data, dtype=np.int16)
        if self.data.ndim != 2:
            raise MapError(f"OccupancyGrid: data must be 2-D, got shape {self.data.shape}")
        if not self.resolution > 0:
            raise MapError(f"OccupancyGrid: resolution must be > 0, got {self.resolution}")

    @property
    def width(self) -> int:
        return int(self.data.shape[1])

    @property
    def height(self) -> int:
        return int(self.data.shape[0])

    def world_to_map(self, wx: float, wy: float) -> tuple[int, int] | None:
        """Cell (mx, my) holding a world point (origin yaw respected), or None outside the grid."""
        dx, dy = wx - self.origin.x, wy - self.origin.y
        c, s = math.cos(self.origin.theta), math.sin(self.origin.theta)
        lx, ly = c * dx + s * dy, -s * dx + c * dy
        if lx < 0 or ly < 0:
            return None
        mx, my = int(lx / self.resolution), int(ly / self.resolution)
        if mx >= self.width or my >= self.height:
            return None
        return mx, my

    def map_to_world(self, mx: float, my: float) -> tuple[float, float]:
        """World position of the centre of cell (mx, my)."""
        lx, ly = (mx + 0.5) * self.resolution, (my + 0.5) * self.resolution
        c, s = math.cos(self.origin.theta), math.sin(self.origin.theta)
        return self.origin.x + c * lx - s * ly, self.origin.y + s * lx + c * ly

    def counts(self) -> dict[str, int]:
        """Number of occupied (>= 65 in scale terms, i.e. 100), free (0) and unknown (-1) cells."""
        return {"occupied": int(np.count_nonzero(self.data == OCCUPIED)),
                "free": int(np.count_nonzero(self.data == FREE)),
                "unknown": int(np.count_nonzero(self.data == UNKNOWN))}


# ---------------------------------------------------------------- images


def read_pnm(path: str) -> np.ndarray:
    """Read a P5 (binary) or P2 (ASCII) greymap into a (rows, cols) float64 array scaled to 0..255."""
    raw = read_bytes(path, limit=MAX_IMAGE_BYTES, what="image", error=MapError)
    magic = raw[:2]
    if magic not in (b"P5", b"P2"):
        raise MapError(f"{path}: bad header: expected PGM magic 'P5' or 'P2', got {magic!r}")
    # Header: magic, width, height, maxval, separated by whitespace, '#' comments allowed.
    tokens: list[bytes] = []
    i = 2
    while len(tokens) < 3:
        while i < len(raw) and raw[i:i + 1].isspace():
            i += 1
        if i >= len(raw):
            raise MapError(f"{path}: bad header: ends before width, height and maxval")
        if raw[i:i + 1] == b"#":
            while i < len(raw) and raw[i:i + 1] not in (b"\n", b"\r"):
                i += 1
            continue
        j = i
        while j < len(raw) and not raw[j:j + 1].isspace() and raw[j:j + 1] != b"#":
            j += 1
        tokens.append(raw[i:j])
        i = j
    try:
        width, height, maxval = (int(t) for t in tokens)
    except ValueError:
        raise MapError(f"{path}: bad header: width/height/maxval not integers: {tokens!r}") from None
    if width <= 0 or height <= 0 or not 0 < maxval < 65536:
        raise MapError(f"{path}: bad header: width={width} height={height} maxval={maxval}")
    _check_cells(path, width, height)
    if magic == b"P5":
        i += 1  # exactly one whitespace byte ends the header
        dtype = np.uint8 if maxval < 256 else np.dtype(">u2")
        n = width * height * np.dtype(dtype).itemsize
        body = raw[i:i + n]
        if len(body) < n:
            raise MapError(f"{path}: truncated image data: {len(body)} of {n} bytes "
                           f"for {width}x{height}")
        pix = np.frombuffer(body, dtype=dtype).reshape(height, width).astype(np.float64)
    else:
        text = b" ".join(line.split(b"#")[0] for line in raw[i:].splitlines())
        try:
            values = np.array(text.split(), dtype=np.int64)
        except ValueError:
            raise MapError(f"{path}: P2 image data holds a non-integer value") from None
        if values.size < width * height:
            raise MapError(f"{path}: truncated image data: {values.size} of "
                           f"{width * height} values")
        pix = values[:width * height].reshape(height, width).astype(np.float64)
    if maxval != 255:
        pix = pix * (255.0 / maxval)
    return pix


def _check_cells(path: str, width: int, height: int) -> None:
    if width * height > MAX_MAP_CELLS:
        raise MapError(f"{path}: image of {width} x {height} pixels is larger than the limit of "
                       f"{MAX_MAP_CELLS} cells")


def _channels(path: str, data: bytes) -> tuple[np.ndarray, bool]:
    """The pixels of a PNG (or other Pillow format) as map_server's SDL_image surface holds them.

    SDL_image strips 16-bit samples to their high byte, expands grey of 1/2/4 bits to 0..255,
    turns grey+alpha into RGBA, keeps a palette image as its indices (map_server reads the index
    byte) unless several palette entries are translucent (then RGBA). Returns an array
    (rows, cols, channels) of uint8 and whether the last channel is alpha.
    """
    import io
    import warnings
    from PIL import Image
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            img = Image.open(io.BytesIO(data))
            _check_cells(path, img.width, img.height)
            img.load()
    except MapError:
        raise
    except Exception as e:  # Pillow raises many types for a broken file
        raise MapError(f"{path}: cannot decode image: {e}") from None
    mode = img.mode
    if mode in ("I;16", "I;16B", "I;16L", "I"):
        # 16-bit grey: the high byte, as png_set_strip_16 gives it.
        arr = (np.asarray(img, dtype=np.uint32) >> 8).astype(np.uint8)
        return arr[:, :, None], False
    if mode == "P":
        trans = img.info.get("transparency")
        if not isinstance(trans, bytes):
            return np.asarray(img, dtype=np.uint8)[:, :, None], False
        img, mode = img.convert("RGBA"), "RGBA"
    if mode in ("1", "L"):
        return np.asarray(img.convert("L"), dtype=np.uint8)[:, :, None], False
    if mode == "LA":
        g, a = np.asarray(img, dtype=np.uint8).transpose(2, 0, 1)
        return np.stack([g, g, g, a], axis=2), True
    if mode == "RGB":
        return np.asarray(img, dtype=np.uint8), False
    if mode != "RGBA":
        img = img.convert("RGBA")
    return np.asarray(img, dtype=np.uint8), True


def _read_image(path: str, mode: str) -> tuple[np.ndarray, np.ndarray | None]:
    """Grey average and alpha channel (or None) of an image file, as map_server computes them."""
    if path.lower().endswith((".pgm", ".pnm")):
        return read_pnm(path), None
    arr, has_alpha = _channels(path, read_bytes(path, limit=MAX_IMAGE_BYTES, what="image",
                                                error=MapError))
    n = arr.shape[2]
    alpha = arr[:, :, -1] if has_alpha else None
    # map_server averages every channel in trinary mode or without alpha, else all but alpha;
    # the sum is an integer, divided as a double.
    k = n if (mode == "trinary" or not has_alpha) else n - 1
    if k == 1:
        return arr[:, :, 0].astype(np.float64), alpha
    total = arr[:, :, :k].sum(axis=2, dtype=np.uint16)
    return total / float(k), alpha


def image_to_grid(avg: np.ndarray, alpha: np.ndarray | None, mode: str, negate: bool,
                  occupied_thresh: float, free_thresh: float) -> np.ndarray:
    """map_server pixel conversion of an image (row 0 = top) into grid values (row 0 = bottom)."""
    if negate:
        avg = 255.0 - avg
    if mode == "raw":
        out = np.floor(avg).astype(np.int16)
    else:
        occ = (255.0 - avg) / 255.0
        out = np.full(avg.shape, UNKNOWN, dtype=np.int16)
        if mode == "scale":
            mid = ~((occ > occupied_thresh) | (occ < free_thresh))
            scaled = 1.0 + 98.0 * (occ - free_thresh) / (occupied_thresh - free_thresh)
            out[mid] = scaled[mid].astype(np.int16)
            if alpha is not None:
                out[mid & (alpha == 0)] = UNKNOWN
        out[occ < free_thresh] = FREE
        out[occ > occupied_thresh] = OCCUPIED
    return np.ascontiguousarray(out[::-1])


# ---------------------------------------------------------------- YAML descriptor


class _Fields:
    """The map descriptor's fields, read one by one; every problem is kept (``file:line:
    field 'x' ...``) so that one load reports them all."""

    def __init__(self, meta: dict, path: str, lines: dict[str, int]) -> None:
        self.meta, self.path, self.lines = meta, path, lines
        self.errors: list[str] = []

    def error(self, key: str, text: str) -> None:
        self.errors.append(f"{self.path}:{self.lines.get(key, 1)}: {text}")

    def get(self, key: str, kind, default=None, required: bool = True):
        meta, path = self.meta, self.path
        if key not in meta:
            if required:
                self.errors.append(f"{path}: missing field '{key}'")
            return default
        value = meta[key]
        if kind is float:
            if not isinstance(value, bool) and isinstance(value, (int, float, str)):
                try:
                    number = float(value)  # a string too, as yaml-cpp's as<double>() reads it
                except ValueError:
                    number = None
                if number is not None:
                    if not math.isfinite(number):
                        self.error(key, f"field '{key}' must be a finite number, got {value!r}")
                        return default
                    return number
        elif kind is bool:
            if isinstance(value, bool) or (isinstance(value, (int, float)) and value in (0, 1)):
                return bool(value)
        elif kind is str and isinstance(value, str):
            return value
        self.error(key, f"field '{key}' must be {kind.__name__}, got {value!r}")
        return default


def load_map(yaml_path: str | os.PathLike) -> OccupancyGrid:
    """Load a map_server YAML descriptor and its image.

    An ``image:`` that does not exist (often an absolute path from another machine) falls back to
    the file of that name beside the YAML. A MapError lists every bad field, one per line.
    """
    path = os.fspath(yaml_path)
    meta, lines = load_yaml_keys(path, what="map file", error=MapError)
    if not isinstance(meta, dict):
        raise MapError(f"{path}: expected a mapping of map fields, got {type(meta).__name__}")
    f = _Fields(meta, path, lines)
    image = f.get("image", str)
    resolution = f.get("resolution", float)
    if resolution is not None and not MIN_RESOLUTION <= resolution <= MAX_RESOLUTION:
        f.error("resolution", f"field 'resolution' must be in [{MIN_RESOLUTION}, "
                f"{MAX_RESOLUTION}] m, got {resolution}")
    origin = meta.get("origin")
    if (not isinstance(origin, (list, tuple)) or len(origin) != 3
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in origin)):
        f.error("origin", f"field 'origin' must be [x, y, yaw], got {origin!r}")
        origin = None
    elif not all(math.isfinite(float(v)) for v in origin) or max(map(abs, origin[:2])) > MAX_ORIGIN:
        f.error("origin", f"field 'origin' must be finite with |x|, |y| <= {MAX_ORIGIN:g} m, "
                f"got {origin!r}")
    negate = f.get("negate", bool)
    occ_th = f.get("occupied_thresh", float)
    free_th = f.get("free_thresh", float)
    if occ_th is not None and free_th is not None and not 0.0 <= free_th < occ_th <= 1.0:
        f.error("free_thresh", f"fields 'free_thresh' ({free_th}) and 'occupied_thresh' "
                f"({occ_th}) must satisfy 0 <= free_thresh < occupied_thresh <= 1")
    mode = f.get("mode", str, "trinary", required=False)
    if mode not in _MODES:
        f.error("mode", f"field 'mode' must be one of {', '.join(_MODES)}, got {mode!r}")
        mode = "trinary"
    image_path = None
    if image is not None:
        image_path = image if os.path.isabs(image) else os.path.join(os.path.dirname(path), image)
        if not os.path.exists(image_path):
            beside = os.path.join(os.path.dirname(path), os.path.basename(image))
            if os.path.exists(beside):
                image_path = beside
            else:
                f.error("image", f"field 'image': file {image!r} not found "
                        f"(nor {os.path.basename(image)!r} beside the YAML)")
                image_path = None
    if image_path is not None:
        try:
            avg, alpha = _read_image(image_path, mode)
        except MapError as e:
            f.errors.append(str(e))
    if f.errors:
        raise MapError("\n".join(f.errors))
    data = image_to_grid(avg, alpha, mode, negate, occ_th, free_th)
    return OccupancyGrid(data, resolution, Pose2D(*(float(v) for v in origin)))


def save_map(grid: OccupancyGrid, yaml_path: str | os.PathLike, image_format: str = "pgm",
             occupied_thresh: float = 0.65, free_thresh: float = 0.196) -> str:
    """Write ``grid`` as map_saver does (trinary: 254 free, 0 occupied, 205 unknown).

    ``image_format`` is ``pgm`` (P5), ``pgm-ascii`` (P2) or ``png``. Returns the image path.
    Cells of 1..99 are written occupied at >= 65 and free at <= 25 (map_saver's thresholds).
    """
    path = os.fspath(yaml_path)
    stem = os.path.splitext(path)[0]
    ext = {"pgm": ".pgm", "pgm-ascii": ".pgm", "png": ".png"}.get(image_format)
    if ext is None:
        raise MapError(f"save_map: image_format must be pgm, pgm-ascii or png, got {image_format!r}")
    image_path = stem + ext
    d = grid.data
    img = np.full(d.shape, 205, dtype=np.uint8)
    img[(d >= 0) & (d <= 25)] = 254
    img[d >= 65] = 0
    img = img[::-1]
    h, w = img.shape
    if image_format == "pgm":
        with open(image_path, "wb") as f:
            f.write(b"P5\n# CREATOR: navbt save_map %.3f m/pix\n%d %d\n255\n" % (grid.resolution, w, h))
            f.write(img.tobytes())
    elif image_format == "pgm-ascii":
        with open(image_path, "w", encoding="ascii") as f:
            f.write(f"P2\n# CREATOR: navbt save_map\n{w} {h}\n255\n")
            for row in img:
                f.write(" ".join(map(str, row.tolist())) + "\n")
    else:
        from PIL import Image
        Image.fromarray(img, mode="L").save(image_path)
    meta = {"image": os.path.basename(image_path), "resolution": float(grid.resolution),
            "origin": [float(grid.origin.x), float(grid.origin.y), float(grid.origin.theta)],
            "negate": 0, "occupied_thresh": occupied_thresh, "free_thresh": free_thresh,
            "mode": "trinary"}
    with open(path, "w", encoding="utf-8") as f:
        yaml.safe_dump(meta, f, sort_keys=False)
    return image_path
