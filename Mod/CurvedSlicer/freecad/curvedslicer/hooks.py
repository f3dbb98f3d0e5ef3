"""What the GUI lends the App side, installed by init_gui.py at FreeCAD's start-up.

The App side (``objects/``, ``stages/``, ``api.py``, ``geometry.py``, ``core.py``,
``preferences.py``) never imports a GUI module (FreeCADGui, PySide, ``viewproviders/``,
``taskpanels/``, ``commands/``, ``gui_progress``). Where it needs the GUI — a progress dialog for a
long run, a view provider for a new or reloaded Job — it calls these hooks. Headless nothing is
installed and the calls do nothing (no progress, no view provider).
"""

_progress_factory = None  # () -> callable(stage: str, fraction: float) -> bool; may have close()
_attach_view = None  # (job) -> None: gives a new Job its view provider
_restore_view = None  # (job) -> None: after a document load (view provider, styling)


def install(progress_factory=None, attach_view=None, restore_view=None):
    """Installs the GUI's callbacks (init_gui.py); None leaves a hook unchanged."""
    global _progress_factory, _attach_view, _restore_view
    if progress_factory is not None:
        _progress_factory = progress_factory
    if attach_view is not None:
        _attach_view = attach_view
    if restore_view is not None:
        _restore_view = restore_view


def make_progress():
    """A new progress callback (the GUI's dialog with Cancel), or None headless. Close it with
    close_progress."""
    return _progress_factory() if _progress_factory is not None else None


def close_progress(progress):
    if progress is not None and hasattr(progress, "close"):
        progress.close()


def attach_view(job):
    """Gives a new Job its view provider (no-op headless)."""
    if _attach_view is not None:
        _attach_view(job)


def restore_view(job):
    """After a document load: the view provider of a Job saved headless, colours (no-op
    headless)."""
    if _restore_view is not None:
        _restore_view(job)
