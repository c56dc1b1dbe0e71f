"""Stability theory: singular perturbation (chapter 5), composite Lyapunov functions, region-of-attraction estimates."""
