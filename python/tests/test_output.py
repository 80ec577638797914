"""Run outputs: the preview and plot are tested in test_preview.py, the glTF file in test_gltf.py (validated the way
the Khronos validator checks it, shared meshes, materials, poses and links read back)."""
