"""Where uma's generic wireframe puts its points, in the frontal plane.

Units: model coordinates (x to the viewer's right, y up; a unit is about 10 cm, chin at
y = -0.82), from landmark proportions of an average adult face. `uma.face.build` turns them into
the wireframe.
"""

from __future__ import annotations

__all__ = ["FACE_POINTS", "MPEG4_POINTS"]

# name: (x, y); x >= 0 points are mirrored to the viewer's left (x < 0) unless on the midline.
# MPEG-4 names are given to the points the standard defines ("l" = subject's left = x > 0).
FACE_POINTS = {
    # midline
    "forehead_top": (0.0, 1.10),
    "forehead_mid": (0.0, 0.80),
    "glabella": (0.0, 0.48),
    "nose_bridge_top": (0.0, 0.30),
    "nose_bridge": (0.0, 0.10),
    "nose_tip": (0.0, -0.12),
    "subnasale": (0.0, -0.22),
    "upper_lip_top": (0.0, -0.31),
    "upper_lip_inner": (0.0, -0.385),
    "lower_lip_inner": (0.0, -0.395),
    "lower_lip_bottom": (0.0, -0.48),
    "mentolabial": (0.0, -0.58),
    "chin": (0.0, -0.72),
    "chin_bottom": (0.0, -0.82),
    # contour, top to bottom
    "temple_top": (0.40, 1.02),
    "temple": (0.62, 0.82),
    "contour_brow": (0.68, 0.50),
    "contour_eye": (0.70, 0.20),
    "contour_cheek": (0.67, -0.10),
    "jaw_corner": (0.58, -0.42),
    "jaw_low": (0.46, -0.64),
    "jaw_chin": (0.30, -0.77),
    "chin_side": (0.15, -0.81),
    # forehead
    "forehead_side": (0.28, 0.82),
    "forehead_outer": (0.50, 0.74),
    # brows
    "brow_inner": (0.13, 0.49),
    "brow_mid": (0.32, 0.56),
    "brow_outer": (0.52, 0.50),
    # eyes
    "eye_inner": (0.15, 0.30),
    "eyelid_upper": (0.31, 0.36),
    "eye_outer": (0.46, 0.30),
    "eyelid_lower": (0.31, 0.25),
    "pupil": (0.31, 0.30),
    "eyelid_upper_inner": (0.22, 0.35),
    "eyelid_upper_outer": (0.40, 0.35),
    # under the eyes, cheeks
    "under_eye": (0.30, 0.14),
    "cheekbone": (0.52, 0.12),
    "cheek_outer": (0.60, -0.08),
    "cheek": (0.40, -0.16),
    "cheek_low": (0.48, -0.34),
    # nose
    "nose_side_top": (0.08, 0.18),
    "nose_side": (0.09, -0.02),
    "nostril_wing": (0.15, -0.15),
    "nostril": (0.07, -0.20),
    # mouth
    "lip_corner": (0.25, -0.39),
    "upper_lip_side": (0.12, -0.325),
    # 2 mm higher than the middle, so the inner mouth's quads are no Delaunay tie (which would
    # split them asymmetrically).
    "upper_lip_inner_side": (0.12, -0.383),
    "lower_lip_inner_side": (0.12, -0.395),
    "lower_lip_side": (0.12, -0.47),
    "nasolabial": (0.30, -0.28),
    # jaw and chin
    "jaw_mid": (0.32, -0.58),
    "chin_inner": (0.16, -0.68),
}

# MPEG-4 FDP feature point -> (uma point name, side): side "l" is x > 0, "r" its mirror.
MPEG4_POINTS = {
    "2.1": ("chin_bottom", "m"),
    "2.2": ("upper_lip_inner", "m"),
    "2.3": ("lower_lip_inner", "m"),
    "2.4": ("lip_corner", "l"),
    "2.5": ("lip_corner", "r"),
    "2.6": ("upper_lip_inner_side", "l"),
    "2.7": ("upper_lip_inner_side", "r"),
    "2.8": ("lower_lip_inner_side", "l"),
    "2.9": ("lower_lip_inner_side", "r"),
    "2.10": ("chin", "m"),
    "2.11": ("chin_side", "l"),
    "2.12": ("chin_side", "r"),
    "2.13": ("jaw_corner", "l"),
    "2.14": ("jaw_corner", "r"),
    "3.1": ("eyelid_upper", "l"),
    "3.2": ("eyelid_upper", "r"),
    "3.3": ("eyelid_lower", "l"),
    "3.4": ("eyelid_lower", "r"),
    "3.5": ("pupil", "l"),
    "3.6": ("pupil", "r"),
    "3.7": ("eye_outer", "l"),
    "3.8": ("eye_outer", "r"),
    "3.11": ("eye_inner", "l"),
    "3.12": ("eye_inner", "r"),
    "4.1": ("brow_inner", "l"),
    "4.2": ("brow_inner", "r"),
    "4.3": ("brow_mid", "l"),
    "4.4": ("brow_mid", "r"),
    "4.5": ("brow_outer", "l"),
    "4.6": ("brow_outer", "r"),
    "8.1": ("upper_lip_top", "m"),
    "8.2": ("lower_lip_bottom", "m"),
    "8.3": ("lip_corner", "l"),
    "8.4": ("lip_corner", "r"),
    "8.5": ("upper_lip_side", "l"),
    "8.6": ("upper_lip_side", "r"),
    "8.7": ("lower_lip_side", "l"),
    "8.8": ("lower_lip_side", "r"),
    "9.1": ("nostril", "l"),
    "9.2": ("nostril", "r"),
    "9.3": ("nose_tip", "m"),
    "9.15": ("nose_bridge", "m"),
    "11.1": ("forehead_top", "m"),
}
