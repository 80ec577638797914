"""The viewer (``Run.show``, ``World.show``, ``Run.export_viewer``): the scene viser holds at each frame, the
arguments, and the page itself loaded in headless Chromium (Debian's package, driven through playwright) with its
screenshot checked: the scene's ball drawn in enough pixels, and gone when the ball is hidden."""

from __future__ import annotations

import io
import shutil
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import tumble

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (apt-get install chromium)")


@pytest.fixture
def viser() -> Any:
    return pytest.importorskip("viser", reason='the viewer needs viser: pip install "./python[viewer]"')


def poll(until: Callable[[], Any], seconds: float, what: str, pause: float = 0.1) -> Any:
    """``until()``'s first true value within ``seconds``, else a failure naming ``what``."""
    end = time.monotonic() + seconds
    while True:
        value = until()
        if value:
            return value
        if time.monotonic() > end:
            pytest.fail(f"timed out after {seconds} s waiting for {what}")
        time.sleep(pause)


def unit(q: np.ndarray) -> np.ndarray:
    """Quaternions with w >= 0 (q and -q are one rotation)."""
    q = np.asarray(q, dtype=float)
    return q * np.where(q[..., :1] < 0, -1.0, 1.0)


@pytest.fixture(scope="module")
def dominoes() -> tumble.Run:
    return tumble.scenes.dominoes(count=6).run(0.5)


@pytest.fixture
def viewer(viser: Any, dominoes: tumble.Run) -> Iterator[Any]:
    with dominoes.show(port=0, block=False) as shown:
        yield shown


def test_seek_poses_the_scene(viewer: Any, dominoes: tumble.Run) -> None:
    run, scene = dominoes, viewer.server.scene
    boxes = scene.get_handle_by_name("/bodies/box_0")  # the dominoes: one box mesh, an instance per domino
    points = scene.get_handle_by_name("/contacts/points")
    assert boxes is not None and points is not None
    assert scene.get_handle_by_name("/ground/plane_0") is not None  # the floor, a half-space
    for k in (0, 7, run.frames // 2, -1):
        viewer.seek(k)
        k %= run.frames
        assert viewer.frame == k
        np.testing.assert_allclose(boxes.batched_positions, run.body_positions[k, 1:], atol=1e-6)
        np.testing.assert_allclose(unit(boxes.batched_wxyzs), unit(run.body_orientations[k, 1:]), atol=1e-6)
        contacts = run.contacts(k)
        assert points.visible == bool(len(contacts))
        if len(contacts):
            np.testing.assert_allclose(points.points, contacts[:, 0], atol=1e-6)
        assert f"t = {run.times[k]:.3f} s" in viewer._title.content


def test_named_bodies_carry_their_names_above_them(viewer: Any, dominoes: tumble.Run) -> None:
    # the built-in dominoes are named "domino 1" ... "domino 6": a label each, over the domino as it moves
    run, scene = dominoes, viewer.server.scene
    assert run.names[1:] == [f"domino {k}" for k in range(1, 7)]
    for k in (0, run.frames - 1):
        viewer.seek(k)
        for b in range(1, 7):
            label = scene.get_handle_by_name(f"/labels/body_{b}")
            assert label is not None and label.visible
            above = np.asarray(label.position) - run.body_positions[k, b]
            assert np.allclose(above[:2], 0.0, atol=1e-6) and above[2] > 0.0


def test_the_plots_beside_the_scene_follow_what_the_run_has(viser: Any, dominoes: tumble.Run) -> None:
    # contact: energy and penetration; joints: energy and the anchors' gap; neither: energy only
    cases = [(dominoes, ["Energy (J)", "Largest penetration"]),
             (tumble.scenes.chain().run(0.2), ["Energy (J)", "Joint gap"]),
             (tumble.scenes.cloth().run(0.1), ["Energy (J)"])]
    for run, expected in cases:
        shown = run.show(port=0, block=False)
        try:
            # the unit follows the size (µm for the dominoes, nm for a chain's rounding-level gap)
            assert [p if p.startswith("Energy") else p.split(" (")[0] for p in shown.plots] == expected, shown.plots
        finally:
            shown.stop()


def test_play_advances_and_pause_holds(viewer: Any) -> None:
    viewer.seek(0)
    viewer.play()
    assert viewer.playing
    poll(lambda: viewer.frame >= 3, 10, "playback to advance")
    viewer.pause()
    held = viewer.frame
    time.sleep(0.2)
    assert not viewer.playing and viewer.frame == held


def test_links_and_particles_follow_the_frames(viser: Any) -> None:
    chain = tumble.scenes.chain(links=4).run(0.3)
    with chain.show(port=0, block=False) as shown:
        links = shown.server.scene.get_handle_by_name("/links")
        for k in (0, chain.frames - 1):
            shown.seek(k)
            np.testing.assert_allclose(links.points, chain.link_segments(k), atol=1e-6)
    cloth = tumble.scenes.cloth(n=4).run(0.2)
    with cloth.show(port=0, block=False) as shown:
        particles = shown.server.scene.get_handle_by_name("/particles")
        shown.seek(-1)
        np.testing.assert_allclose(particles.points, cloth.particle_positions[-1], atol=1e-6)


def test_bad_arguments(viser: Any, dominoes: tumble.Run, tmp_path: Path) -> None:
    for port in (-1, 65536, "8080", 80.0, True, None):
        with pytest.raises(ValueError, match="`port`"):
            dominoes.show(port=port, block=False)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="`block`"):
        dominoes.show(port=0, block="no")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="`host`"):
        dominoes.show(port=0, block=False, host="")
    with pytest.raises(ValueError, match="`path`"):
        dominoes.export_viewer(tmp_path / "run.png")
    world = tumble.scenes.bouncing_ball()
    with pytest.raises(ValueError, match="`port`"):
        world.show(1.0, port=-5)
    assert world.time == 0.0  # checked before running
    with pytest.raises(ValueError, match="`duration`"):
        world.show(-1.0, port=0, block=False)
    with dominoes.show(port=0, block=False) as shown:
        for frame in (dominoes.frames, -dominoes.frames - 1, 1.5):
            with pytest.raises(ValueError, match="`frame`"):
                shown.seek(frame)  # type: ignore[arg-type]


def test_world_show_without_duration_shows_it_as_it_is(viser: Any) -> None:
    world = tumble.scenes.pyramid(layers=2)
    world.run(0.3)
    before, contacts = world.time, world.contacts()
    assert len(contacts["points"])
    with world.show(port=0, block=False) as shown:
        assert world.time == before  # not stepped
        assert shown.run.frames == 1 and not shown.playing
        boxes = shown.server.scene.get_handle_by_name("/bodies/box_0")
        np.testing.assert_allclose(boxes.batched_positions, world.bodies.positions[1:], atol=1e-6)
        points = shown.server.scene.get_handle_by_name("/contacts/points")
        assert points.visible
        np.testing.assert_allclose(points.points, contacts["points"], atol=1e-6)
    with world.show(0.1, port=0, block=False) as shown:  # with a duration: runs it and shows the run
        assert shown.run.frames == 7 and world.time == pytest.approx(before + 0.1)


def test_wait_returns_when_stopped(viewer: Any) -> None:
    waiter = threading.Thread(target=viewer.wait)
    waiter.start()
    time.sleep(0.3)
    viewer.stop()
    waiter.join(5)
    assert not waiter.is_alive()
    viewer.stop()  # twice is harmless


# --- in the browser ---------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    if CHROMIUM is None:
        pytest.skip("Chromium not installed (apt-get install chromium)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright not installed (the test extra)")
    with sync_api.sync_playwright() as playwright:
        # the system's Chromium (playwright's own browser download is not used); WebGL by SwiftShader, on the CPU
        chromium = playwright.chromium.launch(executable_path=CHROMIUM, args=[
            "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"])
        yield chromium
        chromium.close()


@pytest.fixture(scope="module")
def ball() -> tumble.Run:
    return tumble.scenes.bouncing_ball().run(0.5)


def screenshot(page: Any) -> np.ndarray:
    """The page's 3-D canvas (the largest canvas) as an (H, W, 3) array."""
    from PIL import Image

    box = page.evaluate("""() => Array.from(document.querySelectorAll('canvas'))
        .map(c => c.getBoundingClientRect()).sort((a, b) => b.width * b.height - a.width * a.height)
        .map(r => ({x: r.x, y: r.y, width: r.width, height: r.height}))[0] || null""")
    clip = None if box is None or box["width"] < 50 else box
    return np.asarray(Image.open(io.BytesIO(page.screenshot(clip=clip))).convert("RGB")).astype(int)


def bluish(image: np.ndarray) -> np.ndarray:
    """The pixels of the ball's blue (the palette's second colour, body 1), lit and shaded: clearly bluer than red;
    not those of viser's axes gizmo in the bottom left corner (its z axis is blue)."""
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    mask = (b > r + 35) & (b >= g)
    mask[-100:, :100] = False
    return mask


def stats(image: np.ndarray) -> dict[str, float]:
    background = np.all(image >= 245, axis=-1)  # viser's white background
    colours = len(np.unique(image.reshape(-1, 3) // 4, axis=0))
    return {"non_background": float(1 - background.mean()), "colours": colours, "ball": int(bluish(image).sum())}


def wait_for_scene(page: Any, seconds: float = 90) -> np.ndarray:
    """Screenshots until the scene shows: the ball in at least 300 pixels and a third of the view not background
    (the scene arrives over the websocket or is decoded from the page, fades in, and is drawn on the CPU)."""
    shot: list[np.ndarray] = []

    def drawn() -> bool:
        shot[:] = [screenshot(page)]
        measured = stats(shot[0])
        return measured["ball"] >= 300 and measured["non_background"] > 1 / 3

    try:
        poll(drawn, seconds, "the scene to be drawn", pause=0.5)
    except pytest.fail.Exception:
        raise AssertionError(f"the scene was not drawn: the last screenshot had {stats(shot[0])}") from None
    return shot[0]


@needs_chromium
def test_page_shows_the_scene(viser: Any, browser: Any, ball: tumble.Run, tmp_path: Path) -> None:
    with ball.show(port=0, block=False) as shown:
        page = browser.new_page(viewport={"width": 800, "height": 500})
        try:
            page.goto(shown.url)
            poll(shown.server.get_clients, 60, "the page to connect")
            shown.seek(10)  # the ball in mid-fall
            image = wait_for_scene(page)
            page.screenshot(path=str(tmp_path / "viewer.png"))
            measured = stats(image)
            print(f"viewer screenshot: {measured}")
            assert measured["colours"] > 200  # shaded, not flat
            # the same view with the ball hidden: its pixels go
            for handle, *_ in shown.scene.groups:
                handle.visible = False
            poll(lambda: stats(screenshot(page))["ball"] < 30, 90, "the ball to go", pause=0.5)
        finally:
            page.close()


@needs_chromium
def test_export_plays_from_disk(viser: Any, browser: Any, ball: tumble.Run, tmp_path: Path) -> None:
    path = ball.export_viewer(tmp_path / "ball.html")
    assert path == tmp_path / "ball.html" and "__VISER_EMBED_DATA__" in path.read_text()
    page = browser.new_page(viewport={"width": 800, "height": 500})
    try:
        page.goto(path.as_uri())  # from disk: no server
        first = wait_for_scene(page)
        page.screenshot(path=str(tmp_path / "export.png"))
        print(f"export screenshot: {stats(first)}")
        assert stats(first)["colours"] > 200

        def height(image: np.ndarray) -> float:
            return float(np.nonzero(bluish(image))[0].mean())

        # it plays: the ball's height on the screen changes as it falls and bounces (the recording loops)
        start = height(first)
        poll(lambda: abs(height(screenshot(page)) - start) > 5, 60, "the ball to move", pause=0.2)
    finally:
        page.close()
