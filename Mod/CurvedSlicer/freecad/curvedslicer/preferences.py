"""Workbench preferences (User parameter:BaseApp/Preferences/Mod/CurvedSlicer); no GUI imports."""

import FreeCAD

PARAM_PATH = "User parameter:BaseApp/Preferences/Mod/CurvedSlicer"


def params():
    return FreeCAD.ParamGet(PARAM_PATH)


def default_voxel_size():
    """mm; the VoxelSize of new Jobs."""
    return params().GetFloat("DefaultVoxelSize", 1.0)


def default_cell_file():
    """The CellFile of new Jobs ("" = none)."""
    return params().GetString("DefaultCellFile", "")


def set_defaults(voxel_size=None, cell_file=None):
    if voxel_size is not None:
        params().SetFloat("DefaultVoxelSize", float(voxel_size))
    if cell_file is not None:
        params().SetString("DefaultCellFile", str(cell_file))
