"""Passive muscle-tendon parameters (dissertation ch. 3): curves, leg geometry and the estimator."""
