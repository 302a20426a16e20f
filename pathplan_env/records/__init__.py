"""Episode records: what an episode showed, step by step, kept in one HDF5 file a run and replayed
without simulating.

- :mod:`.trajectory`: :class:`Episode` (the scene once, then per step the robot's pose, every
  obstacle's state, the agent's plan, the waypoint and command, the step's clearance and outcome),
  and :class:`EpisodeRecorder`, which fills one from a live env;
- :mod:`.store`: :class:`RecordWriter` appends episodes to ``episodes.h5`` as they finish;
  :class:`RecordReader` (:func:`open_records`) reads them back, a bad file named in a ``ValueError``
  (:mod:`.layout`: the file's format, version 3, which both share);
- :mod:`.multi`: a multi-robot episode (:class:`~.multi.MultiEpisode`: every robot's pose, status,
  commands and plans a step), its recorder, and its frames drawn as the live env draws them;
- :mod:`.replay`: :func:`frames`, the episode drawn by the env's own renderer, frame for frame what
  a live run draws;
- :mod:`.social`: the social-navigation metrics computed from a record (jerk, path irregularity,
  time to collision, near misses, personal-space intrusion, distance to humans);
- :mod:`.export`: an episode as CSV rows.

The harness (``agents.evaluation``) records with ``evaluate(..., record=True)``; this package
imports nothing of it. HDF5 (through h5py, the ``records`` extra) because an episode is a few
chunked, compressed arrays that a reader opens one at a time.
"""

from pathplan_env.records.trajectory import Episode, EpisodeRecorder

__all__ = ["Episode", "EpisodeRecorder"]
