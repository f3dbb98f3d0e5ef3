"""GUI commands of the workbench."""
