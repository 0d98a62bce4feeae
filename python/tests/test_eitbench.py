"""The Python package against the command-line tool (EITBENCH_CLI): each function gives what the
C++ program gives for the same input, and bad input raises eitbench.InputError with its message."""
import os
import re
import subprocess

import numpy as np
import pytest

import eitbench

CLI = os.environ.get("EITBENCH_CLI", "eitbench")


def cli(*args):
    done = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = tmp_path_factory.mktemp("data") / "tiny.h5"
    cli("simulate", "--preset", "tiny", "--density", "coarse", "--quiet", "--out", path)
    return path


def tool_cc(tiny, tmp_path, *args):
    """The test split's mean CC that `eitbench reconstruct ARGS` prints for the tiny set."""
    out = cli("reconstruct", *args, "--data", tiny, "--png", "0", "--out", tmp_path / "r.h5")
    return float(re.search(r"CC ([0-9.]+)", out).group(1))


def sensor(data):
    """The Reconstructor arguments that give the data set's own sensor."""
    return dict(background=data["background_conductivity"],
                contact_impedance=data["contact_impedance"], current=data["current"])


def mean_cc(images, labels):
    return np.mean([in_disk_cc(i, l) for i, l in zip(images, labels)])


def in_disk_cc(image, label):
    """CC over the in-disk pixels (pixel centres inside the unit disk), computed here."""
    n = label.shape[-1]
    c = -1 + (np.arange(n) + 0.5) * 2 / n
    mask = (c[None, :] ** 2 + c[:, None] ** 2) <= 1
    return np.corrcoef(image[mask], label[mask])[0, 1]


def test_mesh_equals_the_tools_gmsh_file(tmp_path):
    cli("mesh", "--density", "coarse", "--out", tmp_path / "m.msh")
    read = eitbench.read_mesh(str(tmp_path / "m.msh"))
    made = eitbench.disk_mesh(density="coarse")
    assert read.num_triangles == made.num_triangles == 480
    assert read.num_electrodes == 16 and len(made.electrodes) == 16
    np.testing.assert_allclose(read.nodes, made.nodes, atol=1e-12)
    np.testing.assert_array_equal(read.triangles, made.triangles)


def test_forward_frame_equals_the_tools(tmp_path):
    circles = [[0.3, -0.2, 0.2, 0.5], [-0.4, 0.3, 0.15, 2.0]]
    text = ";".join(",".join(map(str, c)) for c in circles)
    cli("forward", "--density", "coarse", "--circles", text, "--out", tmp_path / "f.csv")
    expected = np.loadtxt(tmp_path / "f.csv", delimiter=",")
    mesh = eitbench.disk_mesh(density="coarse")
    model = eitbench.ForwardModel(mesh)
    sigma = eitbench.conductivity_from_circles(mesh, circles, background=1.0)
    np.testing.assert_allclose(model.frame(sigma), expected, rtol=1e-9, atol=1e-12)
    assert model.measurements == 208


def test_jacobian_against_finite_differences():
    mesh = eitbench.disk_mesh(density="coarse")
    model = eitbench.ForwardModel(mesh)
    sigma = np.full(mesh.num_triangles, 0.05)
    J = model.jacobian(sigma)
    assert J.shape == (104, 480)
    for k in (0, 123, 479):
        h = 1e-7
        up, down = sigma.copy(), sigma.copy()
        up[k] += h
        down[k] -= h
        fd = (model.difference(up, 0.05) - model.difference(down, 0.05)) / (2 * h)
        np.testing.assert_allclose(J[:, k], fd, rtol=1e-5, atol=1e-8 * np.abs(J).max())


def test_augment_equals_the_tools(tmp_path):
    rng = np.random.default_rng(1)
    frames = rng.normal(size=(3, 208))
    np.savetxt(tmp_path / "in.csv", frames, delimiter=",", fmt="%.17g")
    cli("augment", "--in", tmp_path / "in.csv", "--group", "d16", "--out", tmp_path / "out.csv")
    expected = np.loadtxt(tmp_path / "out.csv", delimiter=",")
    got, labels = eitbench.augment(frames, group="d16")
    assert labels is None and got.shape == (3 * 32, 208)
    np.testing.assert_allclose(got, expected, rtol=1e-15)


def test_augmented_labels_follow_their_frames(tiny):
    data = eitbench.read_dataset(str(tiny))
    frames, labels = eitbench.augment(data["differences"][:2], data["labels"][:2], group="rotations")
    assert frames.shape == (32, 104) and labels.shape == (32, 64, 64)
    # a quarter turn (4 of 16 electrode steps) moves the label by 90 degrees: rot90 of the image
    np.testing.assert_allclose(labels[0], data["labels"][0], atol=1e-6)
    turned = labels[12]  # rotation by 12 steps = -4 steps: check either direction
    assert min(np.abs(turned - np.rot90(labels[0], k)).max() for k in (1, 3)) < 0.05


@pytest.mark.parametrize(
    "method",
    ["tikhonov", "noser", "laplace", "smooth", "tv", "gn", "greit", "shape", "shape-linear"])
def test_reconstructors_score_as_the_tool_does(tiny, tmp_path, method):
    data = eitbench.read_dataset(str(tiny))
    test = data["split"] == 2
    weight = {"shape": 2.0, "shape-linear": 4.0}.get(method, 0.01)  # the BIC's penalty, or lambda
    expected = tool_cc(tiny, tmp_path, "--method", method, "--lambda", weight)
    r = eitbench.Reconstructor(method, lambda_=weight, **sensor(data))
    images = r.reconstruct(data["differences"][test])
    assert images.shape == (test.sum(), 64, 64)
    cc = mean_cc(images, data["labels"][test])
    assert abs(cc - expected) < 5e-4, (cc, expected)
    one = r.reconstruct(data["differences"][test][0])  # one frame, and the batch: float32 products
    np.testing.assert_allclose(one, images[0], atol=1e-5 * np.abs(images[0]).max())


@pytest.mark.parametrize("method, option, value",
                         [("smooth", "smooth_length", 0.3), ("noser", "noser_exponent", 1.0)])
def test_prior_options_score_as_the_tools_flags(tiny, tmp_path, method, option, value):
    data = eitbench.read_dataset(str(tiny))
    test = data["split"] == 2
    flag = "--" + option.replace("_", "-")
    expected = tool_cc(tiny, tmp_path, "--method", method, "--lambda", 0.01, flag, value)
    frames, labels = data["differences"][test], data["labels"][test]
    images = eitbench.Reconstructor(method, lambda_=0.01, **sensor(data),
                                    **{option: value}).reconstruct(frames)
    cc = mean_cc(images, labels)
    assert abs(cc - expected) < 5e-4, (cc, expected)
    default = eitbench.Reconstructor(method, lambda_=0.01, **sensor(data)).reconstruct(frames)
    assert np.abs(images - default).max() > 1e-3 * np.abs(default).max()  # the option is used


def test_validation_choice_and_circles(tiny):
    data = eitbench.read_dataset(str(tiny))
    val = data["split"] == 1
    r = eitbench.Reconstructor("noser", choose="validation")
    r.fit(data["differences"][val], data["labels"][val])
    assert "validation" in r.settings
    shape = eitbench.Reconstructor("shape-linear")
    i = int(np.argmax(data["circle_count"] == 1))
    found = shape.touches(data["differences"][i])
    truth = data["circles"][i, 0]
    assert len(found) >= 1
    assert min(np.hypot(c[0] - truth[0], c[1] - truth[1]) for c in found) < 0.05
    assert r.pixel_jacobian.shape[0] == 104 and len(r.pixel_indices) == r.pixel_jacobian.shape[1]


def test_shape_fits_by_count_are_what_the_method_chooses_from(tiny):
    data = eitbench.read_dataset(str(tiny))
    i = int(np.argmax(data["circle_count"] == 1))
    frame = data["differences"][i]
    shape = eitbench.Reconstructor("shape-linear", lambda_=1.0)
    fits = shape.fits_by_count(frame)
    assert fits[0] == (pytest.approx(frame @ frame), [])  # K = 0 explains nothing
    assert [len(circles) for _, circles in fits] == list(range(len(fits)))
    assert fits[1][0] < 1e-2 * frame @ frame  # one touch: one circle explains nearly all of it
    chosen = shape.touches(frame)
    assert any(circles == chosen for _, circles in fits)  # the linear method returns one of them
    # Refitting a fit from its own circles on the same model moves nothing that matters.
    rss, again = shape.fit_from(frame, fits[1][1], "linear")
    assert rss == pytest.approx(fits[1][0], rel=1e-6)
    np.testing.assert_allclose(again, fits[1][1], atol=1e-6)
    with pytest.raises(eitbench.InputError, match="not a shape fit"):
        eitbench.Reconstructor("noser").fits_by_count(frame)


def test_dataset_round_trip(tiny, tmp_path):
    data = eitbench.read_dataset(str(tiny))
    eitbench.write_dataset(str(tmp_path / "copy.h5"), data)
    again = eitbench.read_dataset(str(tmp_path / "copy.h5"))
    for key in ("differences", "frames", "reference", "labels", "split", "circle_count"):
        np.testing.assert_array_equal(again[key], data[key], err_msg=key)
    np.testing.assert_array_equal(np.isnan(again["circles"]), np.isnan(data["circles"]))
    assert "frames" in cli("info", tmp_path / "copy.h5")


def test_press_set_touches_round_trip(tiny, tmp_path):
    # A press set: each frame's known touch (its first circle's centre), a depth where known.
    data = eitbench.read_dataset(str(tiny))
    n = len(data["split"])
    touches = np.full((n, 4, 3), np.nan)
    touches[:, 0, :2] = data["circles"][:, 0, :2]
    touches[::2, 0, 2] = 0.1
    data["touches"], data["touch_size"] = touches, "depth"
    eitbench.write_dataset(str(tmp_path / "press.h5"), data)
    again = eitbench.read_dataset(str(tmp_path / "press.h5"))
    np.testing.assert_array_equal(again["touches"], touches)
    np.testing.assert_array_equal(again["touch_count"], np.ones(n))
    assert again["touch_size"] == "depth"
    assert "touches (a press set)" in cli("info", tmp_path / "press.h5")


def test_learned_model_reconstructs_as_the_tool_does(tiny, tmp_path):
    model_path = tmp_path / "m.pt"
    cli("train", "--data", tiny, "--steps", "4", "--quiet", "--out", model_path)
    expected = tool_cc(tiny, tmp_path, "--method", "dnn", "--model", model_path)
    data = eitbench.read_dataset(str(tiny))
    test = data["split"] == 2
    model = eitbench.load_model(str(model_path))
    images = model.reconstruct(data["differences"][test])
    cc = mean_cc(images, data["labels"][test])
    assert abs(cc - expected) < 5e-4, (cc, expected)
    same = eitbench.Reconstructor("dnn", model=str(model_path)).reconstruct(data["differences"][test])
    np.testing.assert_allclose(same, images, atol=1e-6)


def test_bad_input_raises_with_the_tools_message(tmp_path):
    r = eitbench.Reconstructor("noser", lambda_=0.01, mesh=eitbench.disk_mesh(density="coarse"))
    with pytest.raises(eitbench.InputError, match="103"):
        r.reconstruct(np.zeros(103))
    with pytest.raises(ValueError):  # InputError is a ValueError
        eitbench.Reconstructor("no-such-method")
    with pytest.raises(ValueError, match="missing.h5"):
        eitbench.read_dataset(str(tmp_path / "missing.h5"))
    with pytest.raises(ValueError, match="density"):
        eitbench.disk_mesh(density="dense")


def test_training_from_python_matches_the_tool(tiny, tmp_path):
    data = eitbench.read_dataset(str(tiny))
    tr, va, te = (data["split"] == k for k in (0, 1, 2))
    model = eitbench.train(data["differences"][tr], data["labels"][tr], data["differences"][va],
                           data["labels"][va], augment="d16", steps=4, seed=1)
    assert model.augment == "d16" and model.parameters > 0
    eitbench.save_model(str(tmp_path / "py.pt"), model)
    expected = tool_cc(tiny, tmp_path, "--method", "dnn", "--model", tmp_path / "py.pt")
    images = model.reconstruct(data["differences"][te])
    cc = mean_cc(images, data["labels"][te])
    assert abs(cc - expected) < 5e-4, (cc, expected)
    # The tool's own training with the same options and seed gives the same network. Without
    # augmentation: with it the tool moves each label by re-drawing its circles, the module by
    # resampling the image (train() takes no circles).
    ours = eitbench.train(data["differences"][tr], data["labels"][tr], data["differences"][va],
                          data["labels"][va], steps=4, seed=1)
    cli("train", "--data", tiny, "--steps", "4", "--quiet", "--out", tmp_path / "cli.pt")
    theirs = eitbench.load_model(str(tmp_path / "cli.pt"))
    np.testing.assert_allclose(ours.reconstruct(data["differences"][te]),
                               theirs.reconstruct(data["differences"][te]), atol=1e-5)


def test_pixel_jacobian_equals_the_tools(tmp_path):
    """The reconstructors' pixel Jacobian is the tool's J_pix on the label scale x = -dsigma/sigma0:
    A = -sigma0 J_pix over the in-disk pixels."""
    cli("jacobian", "--density", "coarse", "--conductivity", 0.05, "--values", "reduced", "--basis",
        "pixels", "--out", tmp_path / "j.csv")
    J = np.loadtxt(tmp_path / "j.csv", delimiter=",", ndmin=2)
    r = eitbench.Reconstructor("noser", lambda_=0.01, mesh=eitbench.disk_mesh(density="coarse"),
                               background=0.05)
    assert J.shape == (104, 64 * 64) and r.pixel_jacobian.shape == (104, len(r.pixel_indices))
    expected = -0.05 * J[:, np.array(r.pixel_indices)]
    np.testing.assert_allclose(r.pixel_jacobian, expected, rtol=0, atol=1e-12 * np.abs(expected).max())
