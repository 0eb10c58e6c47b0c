"""``walk3d verify``: replay a prediction in OpenSim and compare its inverse dynamics.

* :mod:`walk3d.verify.compare`: pure comparisons (moments, residuals, stance-foot drift);
* :mod:`walk3d.verify.worker`: the OpenSim calls, run in a child process (OpenSim's wheel
  bundles its own CasADi library, which cannot share a process with walk3d's CasADi);
* :mod:`walk3d.verify.run`: the check of one prediction folder.
"""
