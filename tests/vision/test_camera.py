"""Camera models: projection, view lines and triangulation (Sec. III-A, the SFD)."""

import numpy as np
import pytest

from perception.vision.camera import WORKSPACE_HI, WORKSPACE_LO, default_cameras, triangulate
from perception.world.render import Renderer
from perception.world.scene import Box

CAMS = default_cameras()


@pytest.mark.parametrize("name", ["top", "side"])
def test_default_cameras_see_the_whole_workspace(name):
    cam = CAMS[name]
    corners = np.array([[x, y, z] for x in (WORKSPACE_LO[0], WORKSPACE_HI[0])
                        for y in (WORKSPACE_LO[1], WORKSPACE_HI[1])
                        for z in (WORKSPACE_LO[2], WORKSPACE_HI[2])])
    uv = cam.project(corners)
    assert (uv >= 0).all() and (uv < 256).all()
    assert (cam.depth(corners) > 0).all()


def test_top_camera_looks_down_with_y_up_and_side_camera_sees_z_up():
    top, side = CAMS["top"], CAMS["side"]
    a, b = top.project([[0, 100, 0], [0, 300, 0]])
    assert b[1] < a[1]  # +y is towards the image top
    a, b = top.project([[-100, 200, 0], [100, 200, 0]])
    assert b[0] > a[0]  # +x to the right
    a, b = side.project([[0, 200, 0], [0, 200, 100]])
    assert b[1] < a[1]  # higher is further up in the side image


@pytest.mark.parametrize("name", ["top", "side"])
def test_view_line_passes_through_the_projected_point(name):
    cam = CAMS[name]
    pts = np.array([[-250.0, 30.0, 0.0], [120.0, 380.0, 200.0], [0.0, 200.0, 90.0]])
    for p, uv in zip(pts, cam.project(pts), strict=True):
        o, d = cam.view_line(uv)
        assert np.linalg.norm(np.cross(p - o, d)) < 1e-6
        assert (p - o) @ d > 0  # in front of the camera


@pytest.mark.parametrize("point", [(0, 200, 0), (-280, 20, 10), (250, 390, 280), (40, 150, 75)])
def test_triangulate_exact_projections(point):
    p = np.array(point, float)
    xyz = triangulate(CAMS["top"], CAMS["top"].project(p)[0], CAMS["side"],
                      CAMS["side"].project(p)[0])
    assert np.allclose(xyz, p, atol=1e-6)


def _centroid(img: np.ndarray) -> tuple[float, float]:
    """Centre of mass of the bright pixels."""
    ys, xs = np.nonzero(img > 30)  # crease lines (gray 60) belong to the block
    return float(xs.mean()), float(ys.mean())


@pytest.mark.parametrize("center", [(0, 200, 5), (-200, 80, 5), (180, 330, 5), (60, 240, 150),
                                    (-120, 300, 260)])
def test_triangulation_of_a_rendered_small_cube_within_2mm(center):
    renderer = Renderer(CAMS, pixel_noise=2.0, seed=3)
    imgs = renderer.render([Box("block", center, (10.0, 10.0, 10.0))])
    xyz = triangulate(CAMS["top"], _centroid(imgs["top"]), CAMS["side"],
                      _centroid(imgs["side"]))
    assert np.linalg.norm(xyz - np.array(center)) < 2.0


@pytest.mark.parametrize("name", ["top", "side"])
@pytest.mark.parametrize("lo,hi", [((-900, 200, 0), (-850, 250, 45)),  # beside the table
                                   ((0, 200, 900), (50, 250, 950)),  # far above it
                                   ((0, 2000, 0), (50, 2050, 45))],  # far behind it
                         ids=["beside", "above", "behind"])
def test_a_box_outside_the_image_gives_a_one_pixel_rectangle_on_its_edge(name, lo, hi):
    """Round 15 (cli/j, a plan.json whose ACHIEVEs run in reverse): the robot's watch
    searched a region off the image; its window came out inverted and crashed the run."""
    cam = default_cameras()[name]
    x0, y0, x1, y1 = cam.box_region(lo, hi, margin=1)
    w, h = cam.size
    assert 0 <= x0 < x1 <= w and 0 <= y0 < y1 <= h
