"""Host tools of okid: an independent 2-DOF reference and the fmpy verification of the FMUs."""
