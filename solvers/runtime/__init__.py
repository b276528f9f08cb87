"""The application runtime: what every ``lcefem run X``, ``validate`` and ``converge`` shares, one
job per module. Numerics (mechanics, heat, bar-and-hinge, rods) import none of it; they raise
lcefem.models.errors' exceptions and check interrupts through lcefem.solvers.interrupts, and the
command line maps those to exit codes here. Nothing in this package imports FEniCSx or MPI at module
level, so the bar-and-hinge and rod targets start without them.

* :mod:`.exits`: exit codes;
* :mod:`.signals`: SIGINT/SIGTERM handlers (SIGTERM becomes a KeyboardInterrupt, so every
  ``finally`` runs and partial files are kept), PETSc kept off the signals;
* :mod:`.outdir`: the output folder's ownership (marker, lock, --resume/--overwrite) and its flags;
* :mod:`.files`: atomic writers with the ``.part`` convention (a file is complete only under its
  final name; a failed or interrupted run leaves ``*.partial.*``) and disk errors named in one line;
* :mod:`.inputs`: the one decoding path of every file read from the user, and the start-up checks
  of arguments, environment and cache folders (before any library is imported);
* :mod:`.streams`: stdout and stderr guarded (unencodable characters replaced, an unwritable stderr
  never changes the exit status);
* :mod:`.checks`: physical bounds of inputs and of results, and the resolved configuration;
* :mod:`.run`: one run's progress bar, history, outputs, failure.json and summary.json;
* :mod:`.ranks`: rank 0 and barriers without requiring MPI.
"""
