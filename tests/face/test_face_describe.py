import cv2
import numpy as np
import pytest
import skimage.data

from uma.cli import main
from uma.errors import FaceError
from uma.face import (
    describe,
    detect_face,
    fit_points,
    load_description,
    make_params,
    project,
    read_points,
    read_wfm,
    render,
)
from uma.metrics.quality import psnr_db
from uma.paths import codecs_dir


@pytest.mark.parametrize("seed", [5, 6, 7])
def test_render_then_fit_from_points_recovers_parameters(seed, face_model):
    model = face_model
    rng = np.random.default_rng(seed)
    shape = rng.normal(0, 0.3, model.n_shapes)
    actions = rng.uniform(0, 0.6, model.n_actions)
    truth = make_params(
        model,
        tx_px=180,
        ty_px=150,
        scale_px=60,
        rx_rad=rng.uniform(-0.15, 0.15),
        ry_rad=rng.uniform(-0.2, 0.2),
        rz_rad=rng.uniform(-0.1, 0.1),
        actions=actions,
    )
    person = model.personalised(shape)
    clicks = project(person, truth)
    points = {name: tuple(clicks[index]) for name, index in model.feature_points.items()}
    fit = fit_points(model, points, image_shape=(300, 360))
    assert fit
    assert fit.rms_px < 0.1
    assert np.abs(fit.params[:3] - truth[:3]).max() < 0.1  # pixels
    assert np.abs(fit.params[3:6] - truth[3:6]).max() < 0.01  # radians
    # Every vertex, not only the clicked ones, lands where it was.
    fitted = project(model.personalised(fit.shape), fit.params)
    assert np.linalg.norm(fitted - clicks, axis=1).max() < 0.1
    # And the face rendered with the fitted parameters is the face rendered with the truth.
    texture = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2GRAY)[:300, :360]
    source = project(person, make_params(model, tx_px=224, ty_px=118, scale_px=68))
    want = render(texture, source, clicks, model.triangles, (300, 360))
    got = render(texture, source, fitted, model.triangles, (300, 360))
    assert np.array_equal(want.mask, got.mask) or (want.mask != got.mask).sum() < 20
    both = want.mask & got.mask
    assert psnr_db(want.image[both], got.image[both]) > 40


def test_missing_region_fails_with_reason(face_model):
    model = face_model
    points = {"3.5": (10, 10), "3.7": (5, 10), "3.11": (15, 10), "9.3": (20, 30), "8.3": (12, 40)}
    points |= {"8.4": (28, 40), "2.1": (20, 55)}
    fit = fit_points(model, points)
    assert not fit and "right eye" in fit.reason and "3.6" in fit.reason


@pytest.mark.parametrize(
    "points, reason",
    [
        ({"3.5": (10, 10), "3.6": (20, 10)}, "at least 6"),
        (
            {
                "3.5": (10, 10),
                "3.6": (20, 10),
                "9.3": (15, 20),
                "8.3": (12, 30),
                "8.4": (18, 30),
                "2.1": (15, 900),
            },
            "outside",
        ),
        (
            {
                k: (10.0 + i, 10.0 + 2 * i)
                for i, k in enumerate(["3.5", "3.6", "9.3", "8.3", "8.4", "2.1"])
            },
            "one line",
        ),
    ],
)
def test_bad_points_fail_with_reason(points, reason, face_model):
    fit = fit_points(face_model, points, image_shape=(100, 100))
    assert not fit
    assert reason in fit.reason


def test_astronaut_description_round_trips_and_is_small(tmp_path):
    image = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR)
    description = describe(image, read_points(codecs_dir() / "face" / "astronaut.yaml"))
    assert description and description.fit_rms_px < 3.0
    size = description.save(tmp_path / "a.face")
    assert 2_000 < size < 40_000 and size == description.size_bytes
    # Byte-identical from run to run: no time stamps inside.
    import zipfile

    with zipfile.ZipFile(tmp_path / "a.face") as archive:
        assert {i.date_time for i in archive.infolist()} == {(1980, 1, 1, 0, 0, 0)}
    back = load_description(tmp_path / "a.face")
    assert np.allclose(back.projected(), description.projected(), atol=0.01)
    assert back.texture.shape == description.texture.shape


def test_detector_finds_the_astronaut_and_not_a_flat_image():
    gray = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2GRAY)
    box = detect_face(gray)
    assert box and 150 < box.centre[0] < 300 and 60 < box.centre[1] < 200
    assert not detect_face(np.full((200, 200), 255, np.uint8))
    assert not detect_face(cv2.cvtColor(skimage.data.coffee(), cv2.COLOR_RGB2GRAY))


def test_read_points_errors(tmp_path):
    bad = tmp_path / "p.yaml"
    bad.write_text("points:\n  '3.5': [1, two]\n")
    with pytest.raises(FaceError, match=r"p\.yaml:2 \(points\['3\.5'\]\): expected \[x, y\]"):
        read_points(bad)
    with pytest.raises(FaceError, match="no such"):
        read_points(tmp_path / "none.yaml")


def test_describe_cli_writes_description_and_overlay(tmp_path, capsys):
    image = tmp_path / "astro.png"
    cv2.imwrite(str(image), cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR))
    code = main(
        [
            "describe",
            str(image),
            "--points",
            str(codecs_dir() / "face" / "astronaut.yaml"),
            "--out",
            str(tmp_path / "out"),
        ]
    )
    assert code == 0
    assert (tmp_path / "out" / "astro.face").stat().st_size > 0
    assert cv2.imread(str(tmp_path / "out" / "astro.fit.png")) is not None
    assert "bytes" in capsys.readouterr().out


def test_describe_cli_rejects_image_without_face(tmp_path, capsys):
    image = tmp_path / "coffee.png"
    cv2.imwrite(str(image), cv2.cvtColor(skimage.data.coffee(), cv2.COLOR_RGB2BGR))
    code = main(["describe", str(image), "--points", str(codecs_dir() / "face" / "astronaut.yaml")])
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("uma: error:") and "coffee.png" in err and "no face" in err
    bad = tmp_path / "x.png"
    bad.write_text("not an image")
    assert main(["describe", str(bad), "--points", "whatever.yaml"]) == 2


def test_describe_with_candide3(shared_data, tmp_path):
    model = read_wfm(shared_data / "faces" / "candide3" / "candide3.wfm")
    image = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR)
    description = describe(
        image, read_points(codecs_dir() / "face" / "astronaut.yaml"), model=model
    )
    assert description and description.fit_rms_px < 3.0
    assert description.model.n_vertices == 113
    assert description.save(tmp_path / "c.face") == description.size_bytes


def _astronaut():
    image = cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR)
    return image, read_points(codecs_dir() / "face" / "astronaut.yaml")


def test_mirrored_points_fail_with_reason():
    image, points = _astronaut()
    twin = {"3.5": "3.6", "3.7": "3.8", "3.11": "3.12", "3.1": "3.2", "3.3": "3.4", "8.3": "8.4"}
    twin |= {v: k for k, v in twin.items()}
    swapped = {twin.get(k, k): v for k, v in points.items()}
    result = describe(image, swapped)
    assert not result and "mirrored" in result.reason and "swapped" in result.reason


def test_misplaced_point_fails_naming_it():
    image, points = _astronaut()
    points["2.1"] = (points["2.1"][0], 60.0)  # the chin clicked on the forehead
    result = describe(image, points)
    assert not result and "2.1" in result.reason and "px" in result.reason


def test_describe_cli_bad_model_and_unwritable_out(tmp_path, capsys):
    image = tmp_path / "astro.png"
    cv2.imwrite(str(image), cv2.cvtColor(skimage.data.astronaut(), cv2.COLOR_RGB2BGR))
    points = str(codecs_dir() / "face" / "astronaut.yaml")
    model = tmp_path / "m.wfm"
    model.write_text("# VERTEX LIST:\n3\n0 0 0\n1 0 0\n0 1 x\n")
    assert main(["describe", str(image), "--points", points, "--model", str(model)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "line 5 of" in err and "m.wfm" in err
    blocked = tmp_path / "file"
    blocked.write_text("")
    assert main(["describe", str(image), "--points", points, "--out", str(blocked / "d")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "existing file" in err and str(blocked) in err
