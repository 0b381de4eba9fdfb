"""The session's haptic scene over DDS from Python (hapticd.Client.scene(), docs/haptic-scene.md): a real hapticd
on vishard3/dds-scene.yaml (an empty scene), the simulated operator pushing the handle into what the engine adds."""
import time

import numpy as np
import pytest

import hapticd


def sheet(at, n):
    """A flat n x n grid of squares (2 n^2 triangles) in the plane x = at about the y and z axes, 6 cm wide."""
    grid = np.linspace(-0.03, 0.03, n + 1)
    vertices = np.array([[at, y, z] for y in grid for z in grid])
    v = lambda i, j: i * (n + 1) + j  # noqa: E731
    triangles = [t for i in range(n) for j in range(n)
                 for t in ((v(i, j), v(i, j + 1), v(i + 1, j + 1)), (v(i, j), v(i + 1, j + 1), v(i + 1, j)))]
    return vertices, np.array(triangles)


@pytest.mark.domain(97, "dds-scene.yaml")
def test_an_engine_owns_the_scene_the_hand_pushes_what_it_adds(server):
    with hapticd.Client("py-scene", domain=97) as c, hapticd.Client("py-intruder", domain=97) as other:
        c.wait_for_device("vishard3", timeout=20.0, started=True)
        start = c.wait_for_state("vishard3", timeout=5.0).pose.position.copy()
        scene = c.scene()
        with pytest.raises(hapticd.RequestRefused, match="claim the scene first"):
            scene.add({"name": "wall", "shape": "box", "size": [0.01, 0.1, 0.1]})
        scene.claim()
        with pytest.raises(hapticd.RequestRefused, match="claimed by 'py-scene'"):
            other.scene().claim()
        # A wall 2 cm ahead of the handle (the session's world frame), as a dict.
        wall = {"name": "wall", "shape": "plane", "position": [start[0] + 0.02, start[1], start[2]],
                "normal": [-1, 0, 0], "material": {"stiffness": 3000, "damping": 5}}
        assert scene.add(wall) == "added"
        c.operator("vishard3", "push", [15.0, 0.0, 0.0, 0.3])
        time.sleep(1.5)
        held = c.wait_for_state("vishard3", timeout=5.0).pose.position[0] - start[0]
        contacts = scene.contacts()
        assert [(k.device, k.object_name) for k in contacts] == [("vishard3", "wall")]
        pressed = contacts[0].force[0]
        print(f"the wall holds the push: handle at {1e3 * held:.2f} mm, pressing the wall with {pressed:.2f} N")
        assert pressed > 5.0
        assert held == pytest.approx(0.015 + pressed / 3000, abs=0.001)
        # Refusals raise with the server's reason; the wall holds on.
        with pytest.raises(hapticd.RequestRefused, match="radius"):
            scene.add({"name": "ball", "shape": "sphere", "radius": -0.01})
        with pytest.raises(hapticd.RequestRefused, match="must be a JSON object"):
            scene.add("a: &x [1]\nb: *x\n")
        with pytest.raises(hapticd.RequestRefused, match="claimed by"):
            other.scene().remove("wall")
        # A mesh from NumPy arrays, uploaded in parts: a sheet 1 mm behind the wall holds the push once it is gone.
        vertices, triangles = sheet(0.0, 40)
        assert scene.add_mesh({"name": "sheet", "shape": "mesh", "position": [start[0] + 0.021, start[1], start[2]],
                               "material": {"stiffness": 3000, "damping": 5}}, vertices, triangles) == "added"
        scene.remove("wall")
        time.sleep(1.0)
        on_sheet = c.wait_for_state("vishard3", timeout=5.0).pose.position[0] - start[0]
        on = [k for k in scene.contacts() if k.object_name == "sheet"]
        pushed = sum(k.force[0] for k in on)  # the proxy rests on a few of the sheet's triangles at once
        print(f"the sheet holds it: handle at {1e3 * on_sheet:.2f} mm, pressing the sheet with {pushed:.2f} N")
        assert pushed > 5.0
        assert on_sheet == pytest.approx(0.016 + pushed / 3000, abs=0.001)
        with pytest.raises(ValueError):
            scene.add_mesh({"name": "bad", "shape": "mesh"}, [[0, 0, 0]], [[0, 0, -1]])
        # A moving block, moved at 60 Hz; listed; a refused move counted.
        assert scene.add({"name": "block", "shape": "box", "size": [0.02, 0.02, 0.02],
                          "position": [start[0] + 0.2, start[1], start[2]], "moving": True}) == "added"
        for k in range(20):
            assert scene.move("block", hapticd.Pose([start[0] + 0.2, start[1] + 0.001 * k, start[2]]))
            time.sleep(1 / 60)
        assert scene.move("sheet", hapticd.Pose([0, 0, 0]))  # not moving: refused, answered
        deadline = time.time() + 5
        while scene.refused_moves == 0 and time.time() < deadline:
            time.sleep(0.01)
        assert scene.refused_moves == 1 and "moving" in scene.last_refusal
        objects = {o.name: o for o in scene.objects()}
        assert set(objects) == {"sheet", "block"}
        assert objects["sheet"].shape == "mesh" and objects["sheet"].triangles == 3200
        assert objects["block"].moving and objects["block"].pose.position[0] == pytest.approx(start[0] + 0.2)
        scene.release()
        other.scene().claim()
