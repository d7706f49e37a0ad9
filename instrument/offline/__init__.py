"""After the trial: loading, export, the set analyses, the AFO and cohort analyses."""
