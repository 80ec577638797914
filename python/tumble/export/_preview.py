"""The animated preview of a run (GIF, or MP4 through ffmpeg): a small renderer of our own with numpy and Pillow, so
that a preview costs a few milliseconds a frame. Bodies are drawn in their own colours (the palette's where they have
none), shaded by face with their edges, through a depth buffer, so that what is nearer the camera hides what is
behind it; the floor is a gridded square under the scene, springs and joints are lines, particles dots and contacts
red points (springs, particles and contacts hidden where a face is in front of them; ``contacts=False`` leaves the
contacts out). The camera (``_preview_camera``) looks down at the scene from the side, framed on the bounds of
everything that moves (and the floor under it), with the floor at the bottom, or from where ``camera`` says; each
frame carries the scene's name and its time. Frames where nothing moved are merged into one frame held as long as
the stillness lasts, and each frame is held for its own time, to the GIF's 10 ms."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from .._geometry import link_segments, rotation_matrices
from ._preview_camera import TITLE_BAND, Camera, camera_view, check_zoom, frame_camera
from ._preview_mesh import Meshes, floor_quad, gather_meshes, scene_points
from ._preview_raster import DepthBuffer, depth_buffer, in_front, line_pixels, outlines

if TYPE_CHECKING:
    from .._run import Run

__all__ = ["TITLE_BAND", "Camera", "Renderer", "durations_ms", "frame_camera", "preview_frames", "write_preview"]

# The palette: fixed entries, then shades of each body colour (frames are drawn palettised, so no quantisation is
# needed and colours stay exact).
BACKGROUND, TEXT, FLOOR, GRID, EDGE, SPRING, JOINT, PARTICLE, CONTACT, AXIS_X, AXIS_Y, AXIS_Z = range(12)
FIXED = [(246, 247, 249), (20, 20, 20), (222, 224, 228), (190, 193, 200), (40, 44, 52), (200, 120, 40),
         (40, 90, 200), (30, 110, 190), (220, 30, 30), (220, 50, 50), (40, 160, 60), (50, 80, 220)]
FIRST_SHADE = 16
# Shades of each body colour: 24 while the palette's 240 places allow, and never fewer than 6 (more than 40 distinct
# colours are merged into 40 first).
SHADES, FEWEST_SHADES = 24, 6
LIGHT = np.array([0.35, -0.45, 0.82]) / np.linalg.norm([0.35, -0.45, 0.82])
# How far behind the face at its pixel a point or line may lie and still be drawn, in pixels: a contact or a spring
# lies on a surface, which the depth buffer holds at the pixel's centre.
DEPTH_SLACK = 2.0


def colour_palette(colours: np.ndarray) -> tuple[list[int], np.ndarray, int]:
    """The frames' palette for bodies of ``colours`` (B, 3, sRGB): the fixed entries, then the shades of each
    distinct colour, darkest first (a face turned from the light keeps 45% of its colour). Returns the palette (768
    numbers), each body's first shade's index and the number of shades."""
    distinct, which = np.unique(np.asarray(colours, dtype=np.uint8).reshape(-1, 3), axis=0, return_inverse=True)
    room = 256 - FIRST_SHADE
    if len(distinct) > room // FEWEST_SHADES:
        merged = Image.fromarray(distinct[None, :, :]).quantize(colors=room // FEWEST_SHADES,
                                                                 method=Image.Quantize.MEDIANCUT)
        table = np.asarray(merged.getpalette() or [], dtype=np.uint8)[: 3 * (room // FEWEST_SHADES)].reshape(-1, 3)
        distinct, again = np.unique(table[np.asarray(merged)[0]], axis=0, return_inverse=True)
        which = again.ravel()[which.ravel()]
    shades = max(2, min(SHADES, room // max(1, len(distinct))))
    entries = list(FIXED) + [(0, 0, 0)] * (FIRST_SHADE - len(FIXED))
    for r, g, b in distinct.tolist():
        for s in range(shades):
            k = 0.45 + 0.55 * s / (shades - 1)
            entries.append((round(r * k), round(g * k), round(b * k)))
    entries += [(0, 0, 0)] * (256 - len(entries))
    return [c for rgb in entries for c in rgb], FIRST_SHADE + shades * which.ravel(), shades


def _font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1 has only the fixed bitmap font
        return ImageFont.load_default()


class Renderer:
    """Draws a run's frames with one camera: the default view, or from ``position`` towards ``target`` (see
    ``frame_camera``), enlarged ``zoom`` times; with the contacts as red dots or without them."""

    def __init__(self, run: "Run", width: int, position: np.ndarray | None = None,
                 target: np.ndarray | None = None, zoom: float = 1.0, contacts: bool = True) -> None:
        self.run = run
        self.contacts = contacts
        self.meshes: Meshes = gather_meshes(run)
        points = scene_points(run, self.meshes)
        # A body without shapes is drawn as its axes, a quarter of the scene's size long, and framed with them.
        self.axis_length = 0.25 * float(np.ptp(points, axis=0).max())
        if len(self.meshes.bare):
            frames = np.unique(np.linspace(0, run.frames - 1, min(60, run.frames)).round().astype(int))
            tips = rotation_matrices(run.body_orientations[np.ix_(frames, self.meshes.bare)]) * self.axis_length
            centres = run.body_positions[np.ix_(frames, self.meshes.bare)]
            points = np.vstack([points, (centres[..., None, :] + np.swapaxes(tips, -1, -2)).reshape(-1, 3)])
        self.floor = floor_quad(self.meshes, points)
        if self.floor is not None:
            points = np.vstack([points, self.floor[0]])
        self.camera = frame_camera(points, width, position, target, zoom)
        if self.floor is not None:  # seen from below, the floor is left out (it would hide everything on it)
            quad = self.floor[0]
            if np.cross(quad[1] - quad[0], quad[3] - quad[0]) @ self.camera.view[2] <= 0:
                self.floor = None
        self.points = points
        self.size = float(np.ptp(points, axis=0).max())  # the scene's largest extent (m)
        self.font_size = 15
        self.font = _font(self.font_size)
        self._glyphs: dict[str, tuple[Image.Image, tuple[int, int], float]] = {}
        drawn = np.unique(self.meshes.face_body)  # the bodies with faces: only their colours take palette places
        self.palette, first_shade, self.shades = colour_palette(self.meshes.colours[drawn])
        body_shade = np.zeros(len(self.meshes.colours), dtype=np.int64)
        body_shade[drawn] = first_shade
        self.first_shade = body_shade[self.meshes.face_body]  # each face's first shade

    def background(self) -> Image.Image:
        """The picture every frame starts from: the background and the floor with its grid."""
        cam = self.camera
        image = Image.new("P", (cam.width, cam.height), BACKGROUND)
        image.putpalette(self.palette)
        if self.floor is not None:
            draw = ImageDraw.Draw(image)
            quad, grid = self.floor
            draw.polygon([tuple(p) for p in cam.project(quad)[:, :2]], fill=FLOOR)
            for a, b in grid:
                pa, pb = cam.project(np.array([a, b]))[:, :2]
                draw.line([tuple(pa), tuple(pb)], fill=GRID, width=1)
        return image

    def key(self, f: int) -> bytes:
        """Where things are in frame ``f``, to an eighth of a pixel: the bodies' places and turns and the particles.
        Frames with the same key are drawn as one (the contacts of its first frame shown: a body that falls asleep
        drops its contacts from the list without moving)."""
        run, cam = self.run, self.camera
        reach = cam.scale * self.size  # pixels a unit turn can move a point
        parts = [cam.project(run.body_positions[f])[:, :2], run.body_orientations[f] * reach,
                 cam.project(run.particle_positions[f])[:, :2]]
        return np.round(8.0 * np.concatenate([p.ravel() for p in parts])).astype(np.int64).tobytes()

    def scene(self, f: int, base: Image.Image) -> Image.Image:
        """Frame ``f`` without its caption, drawn over a copy of ``base`` (``background()``). Faces go through a
        depth buffer, each pixel showing the nearest; springs, particles and contacts are drawn where no face is in
        front of them, so a cloth behind a ball is hidden by it and a contact behind a wall is not seen; joints and
        bodies without shapes are drawn last, over everything."""
        cam, run = self.camera, self.run
        pixels = np.array(base)
        buffer = self._faces(f, pixels)
        slack = DEPTH_SLACK / cam.scale
        ends = cam.project(link_segments(run, f).reshape(-1, 3)).reshape(-1, 2, 3) if run.links else None
        if ends is not None:
            springs = [i for i, (kind, _, _) in enumerate(run.links) if kind == "spring"]
            rows, columns = line_pixels(buffer, ends[springs], slack)
            pixels[rows, columns] = SPRING
        image = Image.fromarray(pixels)
        image.putpalette(self.palette)
        draw = ImageDraw.Draw(image)
        particles = cam.project(run.particle_positions[f])
        radius = 2 if len(particles) > 100 else 3
        for x, y, _ in particles[in_front(buffer, particles, slack + radius / cam.scale)]:
            draw.ellipse([x - radius, y - radius, x + radius, y + radius], fill=PARTICLE)
        for k, (kind, _, _) in enumerate(run.links):
            if kind != "spring" and ends is not None:
                (ax, ay), (bx, by) = ends[k, 0, :2], ends[k, 1, :2]
                draw.line([(ax, ay), (bx, by)], fill=JOINT, width=2)
                draw.ellipse([ax - 2, ay - 2, ax + 2, ay + 2], fill=JOINT)
        self._bare(draw, f)
        if self.contacts and run.contact_counts[f]:
            points = cam.project(run.contacts(f)[:, 0])
            for x, y, _ in points[in_front(buffer, points, slack)]:
                draw.ellipse([x - 2, y - 2, x + 2, y + 2], fill=CONTACT)
        return image

    def _faces(self, f: int, pixels: np.ndarray) -> DepthBuffer:
        """Draws the bodies' faces at frame ``f`` into ``pixels`` (palette indices, height x width): each face
        turned to the camera shaded by the light, each pixel the nearest face's, with the faces' outlines. Returns
        the depth buffer."""
        cam, m, run = self.camera, self.meshes, self.run
        if not m.faces:
            return DepthBuffer.empty(cam.height, cam.width)
        rotations = rotation_matrices(run.body_orientations[f])
        world = np.einsum("nij,nj->ni", rotations[m.vertex_body], m.vertices) + run.body_positions[f][m.vertex_body]
        normals = np.einsum("nij,nj->ni", rotations[m.face_body], m.normals)
        screen = cam.project(world)
        light = np.clip(normals @ LIGHT, 0.0, 1.0)
        shade = self.first_shade + np.round((0.35 + 0.65 * light) * (self.shades - 1)).astype(np.int64)
        facing = np.flatnonzero((normals @ cam.view[2] > 1e-9)[m.triangle_face])
        buffer = depth_buffer(screen[m.triangles[facing]], m.triangle_face[facing], cam.width, cam.height)
        window = pixels[buffer.window()]
        shown = buffer.face >= 0
        window[shown] = shade[buffer.face[shown]]
        window[outlines(buffer)] = EDGE
        return buffer

    def _bare(self, draw: ImageDraw.ImageDraw, f: int) -> None:
        """Bodies without shapes: a dot at the centre of mass and the body's axes (red x, green y, blue z)."""
        bare = self.meshes.bare
        if not len(bare):
            return
        length = self.axis_length
        centres = self.run.body_positions[f, bare]
        axes = rotation_matrices(self.run.body_orientations[f, bare]) * length  # columns are the body's axes
        for x, r in zip(centres, axes):
            ends = self.camera.project(np.vstack([x, x + r.T]))[:, :2]
            for k, colour in enumerate((AXIS_X, AXIS_Y, AXIS_Z)):
                draw.line([tuple(ends[0]), tuple(ends[k + 1])], fill=colour, width=2)
            draw.ellipse([ends[0][0] - 3, ends[0][1] - 3, ends[0][0] + 3, ends[0][1] + 3], fill=TEXT)

    def caption(self, image: Image.Image, title: str, label: str) -> Image.Image:
        """Writes the scene's name on the left and the time on the right of the top band; returns the image. Each
        character's glyph is rasterised once and pasted (text drawing would otherwise be a third of a preview's
        time)."""
        self._text(image, 8, title)
        self._text(image, self.camera.width - 8 - self._width(label), label)
        return image

    def _glyph(self, ch: str) -> tuple[Image.Image, tuple[int, int], float]:
        if ch not in self._glyphs:
            mask = Image.new("L", (self.font_size * 2, self.font_size * 2), 0)
            ImageDraw.Draw(mask).text((0, 0), ch, fill=255, font=self.font)
            box = mask.getbbox() or (0, 0, 1, 1)
            sharp = mask.crop(box).point(lambda v: 255 if v > 96 else 0).convert("1")  # a palette has no blending
            self._glyphs[ch] = (sharp, (box[0], box[1]), float(self.font.getlength(ch)))
        return self._glyphs[ch]

    def _width(self, text: str) -> int:
        return int(round(sum(self._glyph(ch)[2] for ch in text)))

    def _text(self, image: Image.Image, x: float, text: str) -> None:
        for ch in text:
            mask, (dx, dy), advance = self._glyph(ch)
            if ch != " ":
                image.paste(TEXT, (int(round(x)) + dx, 5 + dy), mask)
            x += advance


def preview_frames(run: "Run", fps: float | None) -> list[int]:
    """The frames a preview shows at ``fps`` (default: the run's own frame rate, at most 30 a second)."""
    if run.frames == 0:
        raise ValueError("invalid argument `run`: the run has no frames to preview")
    frame_dt = float(np.median(np.diff(run.times))) if run.frames > 1 else 1.0
    fps = fps or min(30.0, 1.0 / frame_dt)
    if not (0.0 < fps <= 50.0):
        raise ValueError(f"invalid argument `fps`: a preview shows between 0 and 50 frames a second, got {fps}")
    stride = max(1, round(1.0 / (fps * frame_dt)))
    frames = list(range(0, run.frames, stride))
    if frames[-1] != run.frames - 1:
        frames.append(run.frames - 1)
    return frames


def durations_ms(times: np.ndarray, last: float) -> list[int]:
    """Display times (ms, multiples of the GIF's 10 ms) of frames shown at ``times`` (s), the last held ``last``
    seconds: each frame lasts until the next one's time, rounded so that the rounding never accumulates."""
    ends = np.append(times - times[0], times[-1] - times[0] + last)
    ticks = np.round(ends * 100.0).astype(np.int64)  # centiseconds from the start
    return [int(10 * max(1, d)) for d in np.diff(ticks)]


def write_preview(run: "Run", path: Path, fps: float | None, size: float, title: str | None = None,
                  camera: Any = None, zoom: float = 1.0, contacts: bool = True) -> Path:
    """Writes the preview (see the module's docstring); ``size`` is the picture's longer side in inches at 128
    pixels an inch (the default 5 gives 640 pixels); its shape follows the scene's. ``camera`` is None (the default
    view) or says where the camera looks from and at (``camera_view``); ``zoom`` enlarges the picture about its
    middle; ``contacts`` whether the contacts are drawn."""
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"invalid argument `path`: write a .gif or .mp4, got {path.name!r}")
    if not (np.isfinite(size) and 1.0 <= size <= 40.0):
        raise ValueError(f"invalid argument `size`: the longer side in inches, from 1 to 40, got {size}")
    position, target = camera_view(camera)
    zoom = check_zoom(zoom)
    if not isinstance(contacts, (bool, np.bool_)):
        raise ValueError(f"invalid argument `contacts`: True (draw them) or False, got {contacts!r}")
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise RuntimeError("an .mp4 preview needs ffmpeg on the PATH; write a .gif instead")
    frames = preview_frames(run, fps)
    renderer = Renderer(run, int(round(size * 128)), position, target, zoom, bool(contacts))
    title = title if title is not None else (run.name or "tumble")
    times = run.times[frames]
    # Runs of frames where the picture does not change become one frame, held until the picture changes.
    groups: list[tuple[int, int, bytes]] = []  # first and last index into frames, what they show
    for i, f in enumerate(frames):
        key = renderer.key(f)
        if groups and groups[-1][2] == key:
            groups[-1] = (groups[-1][0], i, key)
        else:
            groups.append((i, i, key))
    step = float(np.median(np.diff(times))) if len(times) > 1 else 1.0 / 30.0
    starts = times[[g[0] for g in groups]]
    durations = durations_ms(starts, step + float(times[-1] - times[groups[-1][0]]))
    pictures = []
    base = renderer.background()
    for first, last, _ in groups:
        a, b = times[first], times[last]
        label = f"t = {a:.2f} s" if last == first else f"t = {a:.2f} to {b:.2f} s, at rest"
        pictures.append(renderer.caption(renderer.scene(frames[first], base), title, label))
    if suffix == ".gif":
        pictures[0].save(path, save_all=True, append_images=pictures[1:], duration=durations, loop=0,
                         optimize=False)
        return path
    _write_mp4(pictures, durations, path)
    return path


def _write_mp4(pictures: list[Image.Image], durations: list[int], path: Path) -> None:
    """Pipes the frames to ffmpeg at 100 frames a second, each repeated for its duration."""
    width, height = pictures[0].size
    command = ["ffmpeg", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s",
               f"{width}x{height}", "-r", "100", "-i", "-", "-pix_fmt", "yuv420p", "-vf", "fps=50", str(path)]
    with subprocess.Popen(command, stdin=subprocess.PIPE) as ffmpeg:
        assert ffmpeg.stdin is not None
        for picture, ms in zip(pictures, durations):
            data = picture.convert("RGB").tobytes()
            for _ in range(ms // 10):  # frame by frame: a long still stretch is not one huge buffer
                ffmpeg.stdin.write(data)
        ffmpeg.stdin.close()
        if ffmpeg.wait() != 0:
            raise RuntimeError(f"ffmpeg failed writing {path}")

