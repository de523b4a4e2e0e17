"""The face model: wireframe (uma's own and Candide-3), geometry, renderer, detector, content
description, and a talking-head source with ground truth. OpenCV is imported where needed."""

from uma.face.clip import describe_clip, picture_of, read_picture, shipped_points
from uma.face.describe import ContentDescription, describe, read_points
from uma.face.description_file import load_description
from uma.face.detect import Box, detect_face, detect_faces, face_of_points
from uma.face.fap import FapSequence, fap_limit, read_fap, write_fap
from uma.face.fap_map import (
    FapUnits,
    fap_sequence,
    fap_units,
    faps_to_parameters,
    parameters_to_faps,
)
from uma.face.fit_points import PointFit, fit_points
from uma.face.geometry import (
    N_POSE,
    POSE_NAMES,
    deform,
    make_params,
    project,
    rotation_matrix,
    visible_triangles,
)
from uma.face.landmarks import IBUG68_TO_MPEG4, read_dlib_xml, read_pts, to_mpeg4
from uma.face.load import load_model
from uma.face.model import FaceModel, save_model
from uma.face.points import MPEG4_POINTS, PointsFile, load_points
from uma.face.region import FaceBoxes, points_box
from uma.face.render import Raster, RenderResult, rasterize, render, sample_bilinear, warp_points
from uma.face.talking_head import Motion, TalkingHeadSource
from uma.face.wfm import read_wfm

__all__ = [
    "detect_faces",
    "face_of_points",
    "fap_limit",
    "MPEG4_POINTS",
    "FaceModel",
    "load_model",
    "save_model",
    "read_wfm",
    "N_POSE",
    "POSE_NAMES",
    "make_params",
    "rotation_matrix",
    "deform",
    "project",
    "visible_triangles",
    "Raster",
    "RenderResult",
    "rasterize",
    "warp_points",
    "sample_bilinear",
    "render",
    "PointFit",
    "fit_points",
    "ContentDescription",
    "describe",
    "load_description",
    "read_points",
    "PointsFile",
    "load_points",
    "describe_clip",
    "read_picture",
    "picture_of",
    "shipped_points",
    "IBUG68_TO_MPEG4",
    "read_pts",
    "read_dlib_xml",
    "to_mpeg4",
    "FapSequence",
    "FapUnits",
    "read_fap",
    "write_fap",
    "fap_units",
    "fap_sequence",
    "faps_to_parameters",
    "parameters_to_faps",
    "Box",
    "detect_face",
    "Motion",
    "TalkingHeadSource",
    "FaceBoxes",
    "points_box",
]
