"""Client against a real femsimp-server: each input kind comes back as itself, groups and fields
carried, progress, cancel, jobs, and failures as FemsimpError with their status."""
import threading
import warnings

import grpc
import meshio
import numpy as np
import pytest

from conftest import Server, box_surface, sphere_surface
import femsimp


def rows(a):
    return {tuple(r) for r in np.asarray(a).tolist()}


def test_numpy_arrays_in_numpy_arrays_out(client):
    points, triangles, _ = box_surface(12)
    out_points, out_triangles = client.simplify((points, triangles), ratio=0.2)
    assert out_points.dtype == np.float64 and out_triangles.shape[1] == 3
    assert len(out_triangles) < len(triangles)
    # femsimp never moves a point: every output point is an input point, exactly.
    assert rows(out_points) <= rows(points)
    assert out_triangles.max() < len(out_points)


def test_groups_and_fields_round_trip(client):
    points, triangles, side = box_surface(12)
    groups = (side + 1).astype(np.uint32)
    pressure = np.where(side == 1, 2.5, 0.0)
    out = client.simplify(femsimp.SurfaceMesh(points, triangles, groups, {"pressure": pressure}),
                          tolerance_relative=0.01)
    assert isinstance(out, femsimp.SurfaceMesh)
    assert len(out.triangles) < len(triangles)
    assert set(out.groups.tolist()) == set(range(1, 7))
    # Each face keeps its side's group and pressure.
    centroid = out.points[out.triangles].mean(axis=1)
    side_of = np.argmax(np.abs(centroid - 0.5), axis=1) * 2 + (
        centroid[np.arange(len(centroid)), np.argmax(np.abs(centroid - 0.5), axis=1)] > 0.5)
    assert np.array_equal(out.groups, side_of + 1)
    assert np.array_equal(out.fields["pressure"], np.where(side_of == 1, 2.5, 0.0))


def test_an_output_that_crosses_itself_warns(client):
    # Two cubes through each other, as a thin wall exported with facets as large as the part
    # crosses itself: repair cannot untangle them, the simplification keeps them.
    points, triangles, _ = box_surface(6)
    both = (np.concatenate([points, points + [0.5, 0.3, 0.2]]),
            np.concatenate([triangles, triangles + len(points)]))
    with pytest.warns(femsimp.FemsimpWarning,
                      match=r"intersects itself: \d+ face pairs cross \(the first: faces \d+ "
                            r"and \d+, at \(.*the input's own crossings"):
        out = client.run(both, ratio=0.5)
    assert out.result.output_crossings.pairs > 0
    assert len(out.result.output_crossings.at) == 3
    # A clean part: no warning, and the count says none.
    with warnings.catch_warnings():
        warnings.simplefilter("error", femsimp.FemsimpWarning)
        clean = client.run(box_surface(6)[:2], ratio=0.5)
    assert clean.result.output_crossings.pairs == 0
    assert not clean.result.output_crossings.cut_short


def test_a_soup_crossing_itself_everywhere_is_counted_to_a_floor(client):
    # 3,000 random facets cross each other millions of times: the server's check stops at
    # 100,000 pairs and says so.
    points = np.random.default_rng(7).random((9000, 3))
    triangles = np.arange(9000).reshape(-1, 3)
    with pytest.warns(femsimp.FemsimpWarning,
                      match=r"intersects itself: at least \d+ face pairs cross \(the check "
                            r"stopped there"):
        out = client.run((points, triangles), ratio=0.5)
    assert out.result.output_crossings.cut_short
    assert out.result.output_crossings.pairs > 100000


def test_bodies_touching_without_shared_vertices_warn(client):
    # A block standing on the cube, exported apart: its bottom lies on the cube's top without a
    # shared vertex. Nothing crosses; the faces overlap in the contact's plane (area 0.25).
    points, triangles, _ = box_surface(4)
    block = points * [0.5, 0.5, 1.0] + [0.2, 0.2, 1.0]  # no corner on one of the cube's corners
    both = (np.concatenate([points, block]), np.concatenate([triangles, triangles + len(points)]))
    with pytest.warns(femsimp.FemsimpWarning,
                      match=r"overlapping faces: \d+ face pairs overlap in their plane, over an "
                            r"area of 0\.25 \(the first: faces \d+ and \d+"):
        out = client.run(both, ratio=0.5)
    overlaps = out.result.output_crossings.overlaps
    assert overlaps.pairs > 0 and abs(overlaps.area - 0.25) < 1e-6
    assert len(overlaps.at) == 3 and abs(overlaps.at[2] - 1.0) < 1e-6
    assert out.result.output_crossings.pairs == 0


def test_a_fold_repair_may_not_undo_warns(client):
    # The unit cube whose top has a facet turned over onto its neighbours (8 inside triangle
    # 4-5-7, the quad given its wrong diagonal). Each facet its own face group: no flip may move
    # the groups' border, so the fold stays, and the client warns as the CLI does.
    points = np.array([[i & 1, i >> 1 & 1, i >> 2 & 1] for i in range(8)] + [[0.7, 0.3, 1]],
                      dtype=np.float64)
    quads = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1]]
    triangles = np.array([t for q in quads for t in ([q[0], q[1], q[2]], [q[0], q[2], q[3]])] +
                         [[4, 5, 7], [7, 8, 4], [7, 6, 8], [6, 4, 8]])
    groups = np.arange(len(triangles), dtype=np.uint32)
    with pytest.warns(femsimp.FemsimpWarning,
                      match=r"folded faces: \d+ face pairs lie on each other in their plane, one "
                            r"of each turned over \(the first: faces \d+ and \d+"):
        out = client.run((points, triangles, groups), ratio=0.5)
    assert out.result.output_crossings.folds.pairs > 0
    assert out.result.repair.counts["fold_left"] == 3
    # The same without groups: repair unfolds it, no warning.
    with warnings.catch_warnings():
        warnings.simplefilter("error", femsimp.FemsimpWarning)
        out = client.run((points, triangles), ratio=0.5)
    assert out.result.repair.counts["unfolded_edge"] == 1
    assert out.result.output_crossings.folds.pairs == 0


def cube_in_a_coating(seam_aside=False):
    # A cube (side 6) inside a coating 2 thick, each written closed: the cube's surface comes
    # twice, facing both ways. `seam_aside`: two unit cubes beside them share an edge (a seam).
    corners = np.array([[i & 1, i >> 1 & 1, i >> 2 & 1] for i in range(8)], dtype=np.float64)
    quads = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]]
    cube = np.array([t for q in quads for t in ([q[0], q[1], q[2]], [q[0], q[2], q[3]])])
    points = [2 + 6 * corners, 10 * corners, 2 + 6 * corners]
    triangles = [cube, cube + 8, (cube + 16)[:, ::-1]]
    if seam_aside:
        points += [corners + [20, 0, 0], corners + [21, 1, 0]]
        triangles += [cube + 24, cube + 32]
    return np.vstack(points), np.vstack(triangles)


def test_a_body_inside_another_sharing_its_surface_is_a_part(client):
    # The surface is kept once and each body is a part: both are in the volume, no warning, and
    # the output has the cube's surface twice again, as the input had it.
    with warnings.catch_warnings():
        warnings.simplefilter("error", femsimp.FemsimpWarning)
        out = client.run(cube_in_a_coating(), ratio=0.5)
    assert out.result.repair.counts["shared_shell"] == 1
    assert out.result.repair.counts["shared_shell_left"] == 0
    assert out.result.input_mass.measure == pytest.approx(1000)
    assert sorted(p.input_volume for p in out.result.parts) == pytest.approx([216, 784])
    points, triangles = out.mesh
    faces = {tuple(np.roll(t, -int(np.argmin(t)))) for t in triangles}
    turned = [t[[0, 2, 1]] for t in triangles]
    both = sum(tuple(np.roll(t, -int(np.argmin(t)))) in faces for t in turned)
    assert both >= 12 and both % 2 == 0


def test_a_body_inside_another_beside_a_seam_is_said(client):
    # With a seam elsewhere in the mesh no parts are made: the surface stays a cavity's wall,
    # which leaves the cube out of the volume: the client warns, as the CLI's report says.
    with pytest.warns(femsimp.FemsimpWarning,
                      match=r"1 closed surface two bodies share kept as a cavity's wall \(the "
                            r"first: closed surface of 12 facets .*\(volume 216\)"):
        out = client.run(cube_in_a_coating(seam_aside=True), ratio=0.5)
    assert out.result.repair.counts["shared_shell_left"] == 1


def test_a_missing_face_is_said_not_filled(client):
    # The unit cube without its top (side 5): a hole of 4 n edges in one plane, a fifth of the
    # surface. Repair leaves it (a tray, or a face the exporter dropped) and says so.
    points, triangles, side = box_surface(4)
    with pytest.warns(femsimp.FemsimpWarning,
                      match=r"the surface is open: repair left 1 hole open \(the first at .*a "
                            r"loop of 16 open edges.*in one plane.*fill_holes='planar'"):
        out = client.run((points, triangles[side != 5]), ratio=0.5)
    assert out.result.repair.counts["hole_left"] == 1
    # The analyst says it is a solid: its flat face is filled in its plane, and it is closed.
    with warnings.catch_warnings():
        warnings.simplefilter("error", femsimp.FemsimpWarning)
        out = client.run((points, triangles[side != 5]), ratio=0.5, fill_holes="planar")
    assert out.result.repair.counts["filled_hole"] == 1
    assert out.result.repair.counts.get("hole_left", 0) == 0
    filled = next(r for r in out.result.repair.records if r.kind == "filled_hole")
    assert "an opening in one plane (16 edges in 1 loop" in filled.detail
    # Closed, nothing to say.
    with warnings.catch_warnings():
        warnings.simplefilter("error", femsimp.FemsimpWarning)
        out = client.run((points, triangles), ratio=0.5)
    assert out.result.repair.counts.get("hole_left", 0) == 0


def test_a_part_far_from_the_origin_keeps_its_digits(client):
    # An assembly's global coordinates: 2 million units out, where float32 is 2^-3 apart (a
    # seventh of this part). The client sends it relative to an origin near it, the result comes
    # back relative to the same origin, and every output point is an input point, exactly.
    points, triangles, _ = box_surface(6)
    far = points + [1000000.0371, 2000000.0813, -300000.0529]
    with warnings.catch_warnings():
        warnings.simplefilter("error", femsimp.FemsimpWarning)
        out = client.run((far, triangles), ratio=0.5)
    assert len(out.result.origin) == 3
    assert abs(out.result.origin[1] - 2000000.58) < 0.125  # the centre, rounded to float32
    # Relative to it the part's floats are 2^-24 apart, not 2^-3.
    assert out.result.coordinates.spacing < 1e-6
    out_points, out_triangles = out.mesh
    assert len(out_triangles) < len(triangles)
    assert rows(out_points) <= rows(far)
    # Placed vertices are not input points: they come back where the engine put them, at the
    # origin plus their float32 offsets, on the part (within the tolerance of its surface).
    ball, ball_triangles = sphere_surface(20)
    centre = np.array([1000000.0371, 2000000.0813, -300000.0529])
    placed_points, _ = client.simplify((ball + centre, ball_triangles), tolerance_relative=0.01,
                                       deviation_check="measured", placement="optimal")
    assert not rows(placed_points) <= rows(ball + centre)
    radius = np.linalg.norm(placed_points - centre, axis=1)
    assert np.abs(radius - 1.0).max() < 0.02 * 2 * np.sqrt(3)  # 1 % of the box's diagonal
    # Near the origin nothing moves: no origin is sent or returned.
    near = client.run((points + [2.0, 0, 0], triangles), ratio=0.5)
    assert len(near.result.origin) == 0


def test_meshio_in_meshio_out(client):
    points, triangles = sphere_surface(30)
    out = client.simplify(meshio.Mesh(points, [("triangle", triangles)]), ratio=0.3)
    assert isinstance(out, meshio.Mesh)
    assert [c.type for c in out.cells] == ["triangle"]
    assert len(out.cells[0].data) < len(triangles)


def test_path_in_path_out(client, tmp_path):
    points, triangles = sphere_surface(30)
    meshio.write(tmp_path / "in.stl", meshio.Mesh(points, [("triangle", triangles)]))
    out = client.simplify(str(tmp_path / "in.stl"), output=tmp_path / "out.obj", ratio=0.3)
    assert out == tmp_path / "out.obj"
    assert len(meshio.read(out).cells[0].data) < len(triangles)


def test_progress_callback_once_per_pass(client):
    points, triangles = sphere_surface(40)
    seen = []
    outcome = client.run((points, triangles), progress=seen.append, ratio=0.05)
    assert [p.number for p in seen] == list(range(1, outcome.result.passes + 1))
    assert all(p.job_id == outcome.job_id for p in seen)
    assert seen[-1].vertices_left == outcome.result.output_vertices
    assert outcome.attempts == 1


def test_progress_bar_drawn_per_pass(client, capsys):
    points, triangles = sphere_surface(20)
    with femsimp.Client(client.address, progress_bar=True) as c:
        outcome = c.run((points, triangles), ratio=0.2)
    err = capsys.readouterr().err
    assert err.count("\r[") == outcome.result.passes
    assert f"pass {outcome.result.passes}:" in err


def test_cancel_on_the_server(client):
    points, triangles = sphere_surface(160)  # ~51 k faces, many small passes
    previous = []

    def on_pass(p):
        if p.number == 1:
            previous.append(client.cancel(p.job_id))

    with pytest.raises(femsimp.FemsimpError) as e:
        client.simplify((points, triangles), progress=on_pass, ratio=0.01, threads=1,
                        candidate_fraction=0.05)
    assert e.value.code == grpc.StatusCode.CANCELLED
    assert previous == ["RUNNING"]
    job = next(j for j in client.jobs() if j.job_id == e.value.job_id)
    assert job.state == "CANCELLED"


def test_cancel_from_the_client(client):
    points, triangles = sphere_surface(160)
    started = threading.Event()

    def on_pass(p):
        client.cancel()  # this client's running calls; not retried
        started.set()

    with pytest.raises(femsimp.FemsimpError) as e:
        client.simplify((points, triangles), progress=on_pass, ratio=0.01, threads=1,
                        candidate_fraction=0.05)
    assert started.is_set()
    assert e.value.code == grpc.StatusCode.CANCELLED and e.value.attempts == 1


def test_jobs_list_the_finished_job(client):
    points, triangles = sphere_surface(10)
    outcome = client.run((points, triangles), label="jobs-test", ratio=0.5)
    job = next(j for j in client.jobs() if j.job_id == outcome.job_id)
    assert job.label == "jobs-test" and job.state == "SUCCEEDED" and job.status_code == "OK"


def test_server_down_is_unavailable_after_the_attempts():
    s = Server()
    address = s.address
    s.stop()
    with femsimp.Client(address, max_attempts=2) as c:
        with pytest.raises(femsimp.FemsimpError) as e:
            c.simplify(sphere_surface(10), ratio=0.5)
    assert e.value.code == grpc.StatusCode.UNAVAILABLE
    assert e.value.attempts == 2 and "gave up after 2 attempts" in str(e.value)
    assert e.value.exit_code == 34


def test_invalid_mesh_is_invalid_argument(client):
    points, triangles = sphere_surface(10)
    doubled = np.concatenate([triangles, triangles[:1]])  # a duplicate facet
    with pytest.raises(femsimp.FemsimpError) as e:
        client.simplify((points, doubled), repair="off")
    assert e.value.code == grpc.StatusCode.INVALID_ARGUMENT
    assert "duplicate" in e.value.details


def test_bad_arrays_refused_before_upload(client):
    points, triangles = sphere_surface(10)
    bad = triangles.copy()
    bad[5, 1] = len(points)
    with pytest.raises(femsimp.MeshError, match=f"face 5 references vertex .* {len(points)} "
                       "points"):
        client.simplify((points, bad))
    nan = points.copy()
    nan[3, 2] = np.nan
    with pytest.raises(femsimp.MeshError, match="vertex 3 has a non-finite coordinate"):
        client.simplify((nan, triangles))


def test_server_option_rule_is_invalid_argument(client):
    # A rule between options is the server's: cell options need the cell back end.
    with pytest.raises(femsimp.FemsimpError) as e:
        client.simplify(sphere_surface(10), cell_ls_cache_kib=100, backend="cell")
    assert e.value.code == grpc.StatusCode.INVALID_ARGUMENT
    assert "ls_cache_kib" in e.value.details


def test_deadline_exceeded(client):
    points, triangles = sphere_surface(160)
    with pytest.raises(femsimp.FemsimpError) as e:
        client.simplify((points, triangles), deadline=0.001, ratio=0.01)
    assert e.value.code == grpc.StatusCode.DEADLINE_EXCEEDED
