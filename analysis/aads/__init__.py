"""The AADS test (dissertation ch. 2): AFO stiffness from motion capture and a force plate by static optimisation.

``load_jig_model`` → ``analyze_trial`` (kinematics → static optimisation → stiffness fits → spring
theory) → ``spring_table`` (Table 2.1) and ``anova_table`` (Table 2.2) over an experiment.
"""

from .model import JigModel, load_jig_model
from .pipeline import AadsTrialResult, analyze_trial

__all__ = ["JigModel", "load_jig_model", "AadsTrialResult", "analyze_trial"]
