"""The preview (``Run.animate``) and the plot (``Run.plot``), read back: framing, captions, timing, still frames
merged, springs and joints drawn, the bodies' colours, the camera, contacts left out, and what is behind a face
hidden; the plot's panels follow what the run has."""

from types import SimpleNamespace

import numpy as np
import pytest
from PIL import Image

import tumble
from tumble import scenes
from tumble.export._preview import BACKGROUND, FIXED, JOINT, SPRING, TEXT, TITLE_BAND, durations_ms

BACKGROUND_RGB = FIXED[BACKGROUND]


def frames_of(path):
    """Each frame of a GIF as an RGB array, and each frame's duration (ms)."""
    out, durations = [], []
    with Image.open(path) as im:
        for k in range(im.n_frames):
            im.seek(k)
            out.append(np.asarray(im.convert("RGB")))
            durations.append(im.info["duration"])
    return out, durations


def drawn_box(frames):
    """The fraction of the picture's width and of its height (below the caption band) that the drawn pixels span,
    over all frames."""
    drawn = np.zeros(frames[0].shape[:2], dtype=bool)
    for f in frames:
        drawn |= (f != BACKGROUND_RGB).any(axis=2)
    drawn = drawn[TITLE_BAND:]
    ys, xs = np.nonzero(drawn)
    return (xs.max() - xs.min() + 1) / drawn.shape[1], (ys.max() - ys.min() + 1) / drawn.shape[0]


# (scene, seconds): bodies on a floor, a long row, a tall pile, a cloth of springs, joints on stairs.
FRAMED = [("dominoes", 2.0), ("bouncing_ball", 1.5), ("pyramid", 0.5), ("cloth", 1.0), ("ragdoll", 1.0),
          ("tumbling_box", 1.0), ("door", 1.0)]


@pytest.mark.parametrize("name,seconds", FRAMED)
def test_the_preview_is_framed_on_the_scene(tmp_path, name, seconds):
    run = getattr(scenes, name)().run(seconds)
    run.name = name
    frames, _ = frames_of(run.animate(tmp_path / f"{name}.gif"))
    wide, high = drawn_box(frames)
    # The camera fits the scene's extent to 92% of the picture along the limiting direction; the picture's other
    # side follows the scene's shape down to half the longer one, so the drawing fills at least half of each.
    assert max(wide, high) > 0.85, (wide, high)
    assert min(wide, high) > 0.5, (wide, high)
    assert wide * high > 0.5, (wide, high)


def test_a_thin_scene_gets_a_narrow_picture(tmp_path):
    # A hanging chain is tall and thin: the picture is at its narrowest (half as wide as high) and the chain spans
    # its height.
    run = scenes.chain().run(0.5)
    frames, _ = frames_of(run.animate(tmp_path / "chain.gif"))
    height, width = frames[0].shape[:2]
    assert width == (height - TITLE_BAND) // 2 + ((height - TITLE_BAND) // 2) % 2
    assert drawn_box(frames)[1] > 0.85


def test_the_floor_is_at_the_bottom(tmp_path):
    # The ball falls onto the floor: the lowest drawn pixels are the floor's (grey), near the picture's bottom, and
    # the ball (blue) is above them in every frame.
    run = scenes.bouncing_ball().run(1.0)
    frames, _ = frames_of(run.animate(tmp_path / "ball.gif"))
    for f in frames:
        rows = np.nonzero((f[TITLE_BAND:] != BACKGROUND_RGB).any(axis=2))[0]
        bottom = f[TITLE_BAND + rows.max()]
        assert rows.max() > 0.9 * (f.shape[0] - TITLE_BAND)
        floor = [c for c in bottom if tuple(c) != BACKGROUND_RGB]
        assert floor and all(abs(int(c[0]) - int(c[2])) < 20 for c in floor)  # grey, not the ball's blue


def test_each_frame_has_the_scene_name_and_its_time(tmp_path):
    run = scenes.bouncing_ball().run(1.0)
    frames, _ = frames_of(run.animate(tmp_path / "ball.gif", title="bouncing ball"))
    text = np.array(FIXED[TEXT])
    band = [(f[:TITLE_BAND] == text).all(axis=2) for f in frames]
    width = frames[0].shape[1]
    assert all(b[:, : width // 2].sum() > 40 for b in band)  # the name, on the left
    assert all(b[:, width // 2:].sum() > 40 for b in band)  # the time, on the right
    # the time changes from frame to frame; the name does not
    assert all((a[:, width // 2:] != b[:, width // 2:]).any() for a, b in zip(band, band[1:]))
    assert all((a[:, : width // 3] == b[:, : width // 3]).all() for a, b in zip(band, band[1:]))


def test_frames_are_held_for_their_own_time(tmp_path):
    # 15 frames a second from a run at 60: every fourth frame, 66.7 ms apart. GIF delays count 10 ms; each frame is
    # held until the next one's time, rounded so that the error never accumulates: the durations add up to the run's
    # length plus the last frame's hold, to the GIF's 10 ms.
    run = scenes.bouncing_ball().run(2.0)
    _, durations = frames_of(run.animate(tmp_path / "ball.gif", fps=15))
    assert all(d % 10 == 0 and d in (60, 70) for d in durations), durations
    assert abs(sum(durations) - 1000 * (2.0 + 4 / 60)) <= 10
    # the rule itself: times 0, 1/15, 2/15 ... with a last hold of 1/15 s
    times = np.arange(31) / 15
    ms = durations_ms(times, 1 / 15)
    assert sum(ms) == round(1000 * (2.0 + 1 / 15), -1) and set(ms) == {60, 70}


def test_a_still_scene_writes_one_frame_held_throughout(tmp_path):
    # A ball lying on the floor (its contact found in a first short run): nothing moves for 3 s, so the preview is
    # one frame lasting 3 s and a frame.
    w = tumble.World(mode="fast")
    w.add_ground()
    w.add_body(tumble.Sphere(0.1), position=(0, 0, 0.1))
    w.run(0.1)
    run = w.run(3.0)
    assert np.ptp(run.body_positions[:, 1], axis=0).max() < 1e-6  # truly at rest (to a micrometre)
    frames, durations = frames_of(run.animate(tmp_path / "still.gif", fps=15))
    assert len(frames) == 1
    assert durations == [round(1000 * (3.0 + 4 / 60), -1)]


def test_springs_and_joints_are_drawn(tmp_path):
    cloth = scenes.cloth().run(0.2)
    frames, _ = frames_of(cloth.animate(tmp_path / "cloth.gif"))
    assert (frames[-1] == FIXED[SPRING]).all(axis=2).sum() > 500  # 900 springs as lines
    chain = scenes.ragdoll().run(0.2)
    frames, _ = frames_of(chain.animate(tmp_path / "ragdoll.gif"))
    assert (frames[0] == FIXED[JOINT]).all(axis=2).sum() > 30  # 9 joints' anchors


def test_bad_preview_arguments_are_refused(tmp_path):
    run = scenes.bouncing_ball().run(0.2)
    with pytest.raises(ValueError, match="`path`"):
        run.animate(tmp_path / "x.png")
    with pytest.raises(ValueError, match="`fps`"):
        run.animate(tmp_path / "x.gif", fps=100)
    with pytest.raises(ValueError, match="`size`"):
        run.animate(tmp_path / "x.gif", size=float("nan"))


def test_the_plot_has_only_the_panels_the_run_needs(tmp_path):
    # A fixed-step run without contact or joints: energy only (no step-size panel of identical steps).
    cloth = scenes.cloth().run(0.2)
    assert [a.get_ylabel() for a in cloth.plot().axes] == ["energy (J)"]
    # contact: penetration; variable steps: the step size
    ball = scenes.bouncing_ball().run(1.5)
    assert [a.get_ylabel() for a in ball.plot().axes] == ["energy (J)", "max penetration (mm)", "step size (s)"]
    # joints: the anchors' gap
    chain = scenes.chain().run(0.5)
    assert [a.get_ylabel() for a in chain.plot().axes] == ["energy (J)", "joint gap (m)"]


def test_the_plot_titles_fit(tmp_path):
    run = scenes.bouncing_ball().run(1.5)
    run.name = "a scene with a rather long name to test that the title wraps"
    fig = run.plot(tmp_path / "plot.png")
    renderer = fig.canvas.get_renderer()
    page = fig.bbox
    texts = [fig._suptitle] + [ax._left_title for ax in fig.axes]
    for text in texts:
        box = text.get_window_extent(renderer)
        assert box.x0 >= page.x0 - 1 and box.x1 <= page.x1 + 1 and box.y1 <= page.y1 + 1, text.get_text()


# Colours, the camera, contacts and depth: small worlds of static boxes seen in one frame.


def first_frame(run, path, **options):
    """The first frame of the run's preview as an RGB array (int, so that channels subtract)."""
    frames, _ = frames_of(run.animate(path, **options))
    return frames[0].astype(int)


def saturated(frame, spread=60):
    """Where the picture below the caption is coloured rather than grey: its channels differ by more than
    ``spread`` (the static bodies' grey, the edges, the floor and the text differ by at most 5)."""
    out = np.ptp(frame, axis=2) > spread
    out[:TITLE_BAND] = False
    return out


def hued(frame, channel):
    """Where the picture is pure red (``channel`` 0) or pure blue (2): that channel above 100 and the other two
    under a tenth of it (a shade scales all three channels alike, so a pure colour stays pure in every shade)."""
    others = np.delete(frame, channel, axis=2)
    return (frame[..., channel] > 100) & (others < 0.1 * frame[..., channel : channel + 1]).all(axis=2)


def test_bodies_are_drawn_in_their_colours(tmp_path):
    # Three boxes alike, seen alike: white, blue, and one given no colour (drawn in the palette's grey for still
    # bodies). The pixels around each box's projected centre are its faces'.
    from tumble.export._preview import EDGE, Renderer

    w = tumble.World(mode="fast")
    for x, color in ((-0.6, (1.0, 1.0, 1.0)), (0.0, (0.0, 0.0, 1.0)), (0.6, None)):
        w.add_body(tumble.Box((0.15, 0.15, 0.15)), static=True, position=(x, 0, 0), color=color)
    run = w.run(0.05)
    frame = first_frame(run, tmp_path / "colours.gif")
    centres = Renderer(run, 640).camera.project(run.body_positions[0])[:, :2]

    def faces_near(k):
        x, y = np.round(centres[k]).astype(int)
        window = frame[y - 12 : y + 13, x - 12 : x + 13].reshape(-1, 3)
        keep = (window != FIXED[EDGE]).any(axis=1) & (window != BACKGROUND_RGB).any(axis=1)
        assert keep.sum() > 400  # the box covers its window (25 x 25 px), but for the edges between its faces
        return window[keep]

    white, blue, plain = faces_near(0), faces_near(1), faces_near(2)
    # Blue: each pixel pure blue (shading scales the channels alike: red and green stay 0, to a tenth for rounding).
    assert (blue[:, 2] > 100).all() and (blue[:, :2] <= 0.1 * blue[:, 2:]).all(), blue[:5]
    # White: each pixel grey, its channels equal to 2 (each channel of a shade is rounded on its own)...
    assert (np.ptp(white, axis=1) <= 2).all(), white[:5]
    # ... and, face for face, brighter than the uncoloured box's grey (140, 140, 145) by 255/140 = 1.8: the same
    # faces under the same light take the same shade. 1.6 allows for the windows' few pixels of rounding.
    assert np.median(white.mean(axis=1)) > 1.6 * np.median(plain.mean(axis=1))


def two_boxes():
    """A red box at (1, 1, 0) and a blue one at (-1, -1, 0)."""
    w = tumble.World(mode="fast")
    w.add_body(tumble.Box((0.2, 0.2, 0.2)), static=True, position=(1, 1, 0), color=(1, 0, 0))
    w.add_body(tumble.Box((0.2, 0.2, 0.2)), static=True, position=(-1, -1, 0), color=(0, 0, 1))
    return w.run(0.05)


def test_the_camera_sets_the_direction_of_view(tmp_path):
    # Seen from +x the picture's right is +y, so the red box (y = 1) is right of the blue (y = -1); seen from +y the
    # right is -x, and the red box (x = 1) is left of the blue.
    run = two_boxes()
    from_x = {"position": (6, 0, 0), "target": (0, 0, 0)}
    from_y = SimpleNamespace(position=(0, 6, 0), target=(0, 0, 0))  # an object with the two attributes does too
    for camera, red_right in ((from_x, True), (from_y, False)):
        frame = first_frame(run, tmp_path / "view.gif", camera=camera)
        red, blue = np.nonzero(hued(frame, 0))[1], np.nonzero(hued(frame, 2))[1]
        assert len(red) > 200 and len(blue) > 200  # both boxes in view
        assert (red.mean() > blue.mean()) == red_right, camera


def test_zoom_enlarges_the_picture_about_its_middle(tmp_path):
    # A blue box in the middle of a scene 4 m wide (white boxes at its ends): zoom 2 draws it twice as wide, in a
    # picture of the same size. The width is counted in pixel columns, to 8% (a column or two of rounding at each
    # side of about 50).
    w = tumble.World(mode="fast")
    w.add_body(tumble.Box((0.2, 0.2, 0.2)), static=True, position=(0, 0, 0), color=(0, 0, 1))
    for x in (-2, 2):
        w.add_body(tumble.Box((0.1, 0.1, 0.1)), static=True, position=(x, 0, 0), color=(1, 1, 1))
    run = w.run(0.05)
    widths, shapes = [], []
    for zoom in (1.0, 2.0):
        frame = first_frame(run, tmp_path / "zoom.gif", zoom=zoom)
        columns = np.nonzero(hued(frame, 2).any(axis=0))[0]
        widths.append(columns.max() - columns.min() + 1)
        shapes.append(frame.shape)
    assert shapes[0] == shapes[1]
    assert widths[0] > 40 and abs(widths[1] / widths[0] - 2.0) < 0.16, widths


def test_bad_camera_and_contacts_arguments_are_refused(tmp_path):
    run = two_boxes()
    bad = [("camera", {"camera": "from the left"}), ("camera", {"camera": {"position": (1, 2)}}),
           ("camera", {"camera": {"target": (0, 0, 0)}}), ("camera", {"camera": {"position": (1, 0, float("nan"))}}),
           ("camera", {"camera": {"position": (0, 0, 1), "target": (0, 0, 1)}}),
           ("camera", {"camera": {"position": (0, 0, 1), "up": (0, 1, 0)}}),
           ("zoom", {"zoom": 0.0}), ("zoom", {"zoom": float("inf")}), ("zoom", {"zoom": "2"}),
           ("contacts", {"contacts": "no"})]
    for name, options in bad:
        with pytest.raises(ValueError, match=f"`{name}`"):
            run.animate(tmp_path / "x.gif", **options)


def test_the_floor_is_left_out_seen_from_below(tmp_path):
    # Seen from above, the floor's grey fills much of the picture; from below it would hide everything on it.
    from tumble.export._preview import FLOOR

    w = tumble.World(mode="fast")
    w.add_ground()
    w.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(0, 0, 0.1), color=(0, 0, 1))
    run = w.run(0.05)
    for z, floor in ((2.0, True), (-2.0, False)):
        frame = first_frame(run, tmp_path / "floor.gif", camera={"position": (1, -1, z), "target": (0, 0, 0.1)})
        assert ((frame == FIXED[FLOOR]).all(axis=2).sum() > 1000) == floor, z
        assert hued(frame, 2).sum() > 1000  # the box, seen from either side


def test_each_face_is_turned_as_its_triangles(tmp_path):
    # The chair is one mesh whose faces are many triangles each, with corners in line along their outlines (its seat
    # and back): each face's normal is a unit vector on the side its triangles face, so that no face is taken for
    # one turned away from the camera and left out. 1e-9: rounding of unit vectors.
    from tumble.export._preview_mesh import gather_meshes

    meshes = gather_meshes(scenes.chair().run(1 / 60))
    v, t = meshes.vertices, meshes.triangles
    facing = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    assert np.allclose(np.linalg.norm(meshes.normals, axis=1), 1.0, atol=1e-9)
    assert (np.einsum("ij,ij->i", facing, meshes.normals[meshes.triangle_face]) > 0).all()


def test_contacts_can_be_left_out(tmp_path):
    # A grey box resting on the floor: its contacts at its bottom corners, the nearest of them in sight.
    from tumble.export._preview import CONTACT

    w = tumble.World(mode="fast")
    w.add_ground()
    w.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(0, 0, 0.1), color=(0.5, 0.5, 0.5))
    w.run(0.1)
    run = w.run(0.2)
    assert (run.contact_counts > 0).all()
    red = [(first_frame(run, tmp_path / "c.gif", contacts=shown) == FIXED[CONTACT]).all(axis=2).sum()
           for shown in (True, False)]
    assert red[0] >= 9 and red[1] == 0, red  # a dot is 5 px across


def closed_box(w, inner=0.5, wall=0.05):
    """Six static grey slabs closing a cube of side 2 ``inner`` about the origin."""
    outer = inner + wall
    for axis in range(3):
        half = [outer, outer, outer]
        half[axis] = wall / 2
        for side in (-1, 1):
            at = [0.0, 0.0, 0.0]
            at[axis] = side * (inner + wall / 2)
            w.add_body(tumble.Box(tuple(half)), static=True, position=tuple(at))


def test_a_box_inside_a_closed_box_is_hidden(tmp_path):
    # A blue box falling inside a closed box, in the corner nearest the camera (there its faces are nearer than the
    # middles of the walls hiding it): no coloured pixel at all. The same box above the closed one is seen.
    for z, seen in ((0.35, False), (0.85, True)):
        w = tumble.World(mode="fast")
        closed_box(w)
        w.add_body(tumble.Box((0.08, 0.08, 0.08)), position=(0.35, -0.35, z), color=(0, 0, 1))
        run = w.run(0.05)
        assert run.contact_counts.sum() == 0
        frame = first_frame(run, tmp_path / "inside.gif")
        assert saturated(frame).any() == seen, z


def test_a_contact_behind_a_wall_is_hidden(tmp_path):
    # A ball resting on the floor of a closed box: its contact (and the ball) hidden by the walls in front of it.
    from tumble.export._preview import CONTACT

    w = tumble.World(mode="fast")
    closed_box(w)
    w.add_body(tumble.Sphere(0.1), position=(0.3, -0.3, -0.4), color=(0, 0, 1))
    w.run(0.2)
    run = w.run(0.1)
    assert (run.contact_counts > 0).all()
    frame = first_frame(run, tmp_path / "behind.gif")
    assert not (frame == FIXED[CONTACT]).all(axis=2).any()
    assert not saturated(frame).any()
