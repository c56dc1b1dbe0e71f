"""Steady motions: straight glides (longitudinal)."""
