"""The ship: bow ice waterlines, panels, normals and panel angles; built-in hulls."""
