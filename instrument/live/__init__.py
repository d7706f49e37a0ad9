"""Recording in the lab: acquisition, trial files, sessions, the trial runner and its live checks, device sources."""
