"""Renderer: shading, occlusion, noise, and the cached layer against a full redraw."""

import numpy as np
import pytest

from perception.vision.camera import default_cameras
from perception.world.render import CREASE_GRAY, HAND_GRAY, Renderer
from perception.world.scene import Box

CAMS = default_cameras()


class StubWorld:
    """A scripted stand-in for the world: yields one scene per frame (a recording)."""

    def __init__(self, scenes):
        """Keep the recorded scenes."""
        self.scenes = scenes
        self.t = 0

    def scene(self):
        """The scene of the current frame, advancing the recording."""
        s = self.scenes[min(self.t, len(self.scenes) - 1)]
        self.t += 1
        return s


def _px(name, p):
    """(row, col) of world point p in view ``name``."""
    u, v = CAMS[name].project(np.array(p, float))[0]
    return int(round(v)), int(round(u))


def _clean(scene):
    """Noise-free images of a scene, rendered from scratch."""
    return Renderer(CAMS, pixel_noise=0.0).render_clean(scene)


def test_empty_scene_is_black():
    imgs = _clean([])
    assert all(img.max() == 0 and img.shape == (256, 256) and img.dtype == np.uint8
               for img in imgs.values())


def test_block_faces_are_shaded_apart_and_the_hand_has_its_own_gray():
    block = Box("block", (0, 200, 25), (60, 60, 50))
    hand = Box("hand", (150, 200, 100), (50, 50, 30))
    imgs = _clean([block, hand])
    assert imgs["top"][_px("top", (0, 200, 50))] == 255  # top face
    assert imgs["side"][_px("side", (0, 200, 50))] == 255  # top face seen from the side
    assert imgs["side"][_px("side", (0, 170, 25))] == 170  # front (-y) face
    assert imgs["top"][_px("top", (150, 200, 115))] == HAND_GRAY
    assert imgs["side"][_px("side", (150, 175, 100))] == HAND_GRAY
    assert imgs["top"][_px("top", (-200, 50, 0))] == 0  # table is black


def test_stacked_blocks_are_separated_by_a_crease_in_the_side_view():
    lower = Box("block", (0, 200, 25), (40, 40, 50))
    upper = Box("block", (0, 200, 75), (40, 40, 50))
    side = _clean([lower, upper])["side"]
    column = side[:, _px("side", (0, 180, 50))[1]]
    v_seam = _px("side", (0, 180, 50))[0]
    assert column[v_seam - 1: v_seam + 2].min() == CREASE_GRAY
    assert column[_px("side", (0, 180, 25))[0]] == 170
    assert column[_px("side", (0, 180, 75))[0]] == 170


def test_hand_above_a_block_hides_it_from_the_top_and_a_front_block_hides_the_hand():
    block = Box("block", (0, 200, 25), (40, 40, 50))
    hand = Box("hand", (0, 200, 120), (50, 50, 30))
    front = Box("block", (0, 80, 60), (80, 20, 120))
    imgs = _clean([hand, block, front])
    assert imgs["top"][_px("top", (0, 200, 50))] == HAND_GRAY
    assert imgs["side"][_px("side", (0, 70, 60))] == 170  # the tall front block
    assert HAND_GRAY not in imgs["side"][_px("side", (0, 70, 110))[0] - 2:
                                         _px("side", (0, 70, 110))[0] + 3,
                                         _px("side", (0, 70, 110))[1]]


def test_positive_angle_raises_the_plus_x_end():
    bar = Box("block", (0, 200, 40), (120, 20, 10), angle=0.4)
    side = _clean([bar])["side"]
    ys, xs = np.nonzero(side)
    left = ys[xs < xs.min() + 5].mean()
    right = ys[xs > xs.max() - 5].mean()
    assert right < left - 10  # image rows grow downwards


def _moving_hand_recording(n=40):
    """Scenes of a hand passing over and behind blocks, picking one up on the way."""
    blocks = [Box("block", (-150, 200, 25), (30, 30, 50)),
              Box("block", (100, 120, 5), (120, 100, 10)),
              Box("block", (100, 120, 35), (30, 30, 50)), Box("block", (0, 60, 40), (40, 30, 80))]
    scenes = []
    for k in range(n):
        x, z = -200 + 11.0 * k, 160 - 1.0 * k  # no box ever intersects another
        hand = [Box("hand", (x, 150, z), (50, 50, 30)),
                Box("hand", (x - 20, 150, z - 35), (10, 20, 40)),
                Box("hand", (x + 20, 150, z - 35), (10, 20, 40))]
        moved = list(blocks)
        if k > 20:  # the block under the hand gets picked and carried along
            moved[2] = Box("block", (x, 150, z - 40), (30, 30, 50))
        scenes.append(hand + moved)
    return scenes


def test_cached_layer_composition_equals_a_full_redraw():
    world = StubWorld(_moving_hand_recording())
    fast = Renderer(CAMS, pixel_noise=0.0)
    for _ in range(len(world.scenes)):
        scene = world.scene()
        got, want = fast.render(scene), _clean(scene)
        for name in ("top", "side"):
            assert np.count_nonzero(got[name] != want[name]) == 0, name


def test_noise_has_the_requested_spread_and_is_seeded():
    hand = [Box("hand", (0, 200, 100), (200, 200, 30))]
    a = Renderer(CAMS, pixel_noise=3.0, seed=5)
    frames = [a.render(hand)["top"] for _ in range(5)]
    patch = np.stack([f[100:150, 100:150] for f in frames]).astype(float)
    assert abs(patch.mean() - HAND_GRAY) < 0.3
    assert 2.7 < patch.std() < 3.3
    assert not np.array_equal(frames[0], frames[1])  # fresh noise every frame
    b = Renderer(CAMS, pixel_noise=3.0, seed=5)
    assert np.array_equal(b.render(hand)["top"], frames[0])
    c = Renderer(CAMS, pixel_noise=3.0, seed=6)
    assert not np.array_equal(c.render(hand)["top"], frames[0])


@pytest.mark.parametrize("noise", [0.0, 2.0])
def test_render_returns_fresh_arrays(noise):
    r = Renderer(CAMS, pixel_noise=noise)
    scene = [Box("block", (0, 200, 25), (30, 30, 50))]
    a = r.render(scene)["top"]
    a[:] = 7
    assert r.render(scene)["top"].max() > 200


def test_prepared_box_cache_stays_small_over_a_long_moving_hand_run():
    # A trembling hand never repeats a pose: the renderer must forget old poses instead
    # of piling them up (a large live heap made garbage collection ~8% of a frame).
    r = Renderer(CAMS, pixel_noise=0.0)
    prepared = []
    real = r._prepare
    r._prepare = lambda boxes: (prepared.extend(b.kind for b in boxes), real(boxes))[1]
    blocks = [Box("block", (x, 150, 25), (30, 30, 50)) for x in (-60, 0, 60)]
    sizes = []
    for k in range(600):
        hand = Box("hand", (-100 + k * 0.3, 150, 200 + (k % 7) * 0.1), (50, 50, 30))
        r.render(blocks + [hand])
        sizes.append(len(r._cache))
    assert max(sizes) <= 64 + 2 * 4 + 1
    # Pruning keeps what the last frame showed: the resting blocks are projected once.
    assert prepared.count("block") == 3 and prepared.count("hand") == 600
