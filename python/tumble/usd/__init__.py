"""USD: a run written out (``_write``) and onto the stage it came from (``_over``), and USD Physics read in (``_read``, with ``_shapes``, ``_bodies``, ``_joints`` and ``_values``)."""
