"""Exports of a run: binary glTF (``_gltf``, its springs and joints in ``_gltf_links``) and the animated preview (``_preview``, with its camera, meshes and depth buffer)."""
