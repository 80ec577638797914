"""The interactive 3-D viewer of a run (``_viewer``) and its scene (``_scene``)."""
