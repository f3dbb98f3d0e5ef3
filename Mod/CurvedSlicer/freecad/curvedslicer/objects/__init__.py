"""Document-object proxies (App side only: no FreeCADGui or PySide imports)."""
