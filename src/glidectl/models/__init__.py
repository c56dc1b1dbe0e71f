"""Vector fields ``xdot = f(x, u)`` of glidectl's vehicle models (one right-hand side per model)."""
