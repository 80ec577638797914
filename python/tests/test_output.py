"""Run outputs: the glTF file, read back (the preview and plot: test_preview.py)."""

import numpy as np
import pygltflib

import tumble


def small_run():
    w = tumble.World(integrator="dopri5", rtol=1e-8, atol=1e-10)
    w.add_body(tumble.Box(half_extents=(0.2, 0.3, 0.4)), density=500.0, position=(0, 0, 2), angular_velocity=(1, 2, 3))
    w.add_particle(position=(1, 0, 1), velocity=(0, 1, 3))
    return w.run(1.0, 0.1)


def test_gltf_round_trip(tmp_path):
    run = small_run()
    path = run.export_gltf(tmp_path / "anim.glb")
    gltf = pygltflib.GLTF2().load(str(path))
    # Root, one body, one particle.
    assert len(gltf.nodes) == 3 and gltf.nodes[1].mesh is not None
    blob = gltf.binary_blob()

    def read(accessor_index, width):
        a = gltf.accessors[accessor_index]
        view = gltf.bufferViews[a.bufferView]
        data = np.frombuffer(blob, dtype=np.float32, count=a.count * width, offset=view.byteOffset)
        return data.reshape(a.count, width)

    animation = gltf.animations[0]
    by_target = {(c.target.node, c.target.path): animation.samplers[c.sampler] for c in animation.channels}
    times = read(by_target[(1, "translation")].input, 1)[:, 0]
    np.testing.assert_allclose(times, run.times - run.times[0], atol=1e-6)
    translation = read(by_target[(1, "translation")].output, 3)
    np.testing.assert_allclose(translation, run.body_positions[:, 0], rtol=1e-6, atol=1e-6)
    rotation = read(by_target[(1, "rotation")].output, 4)
    np.testing.assert_allclose(rotation, run.body_orientations[:, 0][:, [1, 2, 3, 0]], atol=1e-6)
    particle = read(by_target[(2, "translation")].output, 3)
    np.testing.assert_allclose(particle, run.particle_positions[:, 0], rtol=1e-6, atol=1e-6)
