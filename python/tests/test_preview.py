"""The preview (``Run.animate``) and the plot (``Run.plot``), read back: framing, captions, timing, still frames
merged, springs and joints drawn; the plot's panels follow what the run has."""

import numpy as np
import pytest
from PIL import Image

import tumble
from tumble import scenes
from tumble._preview import BACKGROUND, FIXED, JOINT, SPRING, TEXT, TITLE_BAND, durations_ms

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
    # the ball (orange) is above them in every frame.
    run = scenes.bouncing_ball().run(1.0)
    frames, _ = frames_of(run.animate(tmp_path / "ball.gif"))
    for f in frames:
        rows = np.nonzero((f[TITLE_BAND:] != BACKGROUND_RGB).any(axis=2))[0]
        bottom = f[TITLE_BAND + rows.max()]
        assert rows.max() > 0.9 * (f.shape[0] - TITLE_BAND)
        floor = [c for c in bottom if tuple(c) != BACKGROUND_RGB]
        assert floor and all(abs(int(c[0]) - int(c[2])) < 20 for c in floor)  # grey, not the ball's orange


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
