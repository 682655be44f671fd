"""import leanfade: the same bytes as `leanfade bake`, views of the levels, errors, the GIL."""
import os
import subprocess
import tempfile
import threading
import time
import unittest

import numpy as np

import leanfade

LEANFADE = os.environ["LEANFADE_EXE"]


def cli_bake(*args):
    subprocess.run([LEANFADE, "bake", *args], check=True, capture_output=True)


def height_map(size, seed, dtype=np.uint8):
    """Smooth hills plus noise, as integer samples."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:size, 0:size] / size
    h = 0.5 + 0.25 * np.sin(2 * np.pi * 3 * x) * np.cos(2 * np.pi * 2 * y)
    h += 0.05 * rng.random((size, size))
    top = np.iinfo(dtype).max
    return np.clip(np.round(h * top), 0, top).astype(dtype)


def normal_map(size, seed, dtype=np.uint8):
    """A tangent-space normal map (OpenGL convention) of a height field, encoded 0.5 n + 0.5."""
    h = height_map(size, seed, np.uint16).astype(np.float64) / 65535 * 40
    gy, gx = np.gradient(h)
    n = np.stack([-gx, gy, np.ones_like(h)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    top = np.iinfo(dtype).max
    return np.round((0.5 * n + 0.5) * top).astype(dtype)


def ktx2_level_bytes(path, level, layer):
    """One layer of one level of a KTX2 file, read through its level index."""
    described = leanfade.info(path)
    entry = described["levels"][level]
    with open(path, "rb") as f:
        f.seek(entry["byte_offset"])
        data = f.read(entry["byte_length"])
    layers = described["layer_count"] or 1
    size = len(data) // layers
    return data[layer * size:(layer + 1) * size]


class SameBytesAsTheCli(unittest.TestCase):
    """leanfade.bake(array).save(p) writes `leanfade bake`'s bytes for the same input."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory(dir=os.environ.get("LEANFADE_TEST_TMP"))
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.dir, name)

    def check(self, name, array, settings, flags):
        source = self.path(name)
        leanfade.write_image(source, array)
        cli_bake(source, "-o", self.path("cli.ktx2"), *flags)
        with open(self.path("cli.ktx2"), "rb") as f:
            expected = f.read()
        with open(source, "rb") as f:
            data = f.read()
        for label, given in (("array", array), ("file", source), ("bytes", data)):
            leanfade.bake(given, **settings).save(self.path("py.ktx2"))
            with open(self.path("py.ktx2"), "rb") as f:
                self.assertEqual(f.read(), expected, f"{name} {settings} from {label}")
        return leanfade.load(self.path("cli.ktx2"))

    def test_height_maps_every_storage(self):
        heights = height_map(192, 1)
        for bits in ("auto", "8", "16", "16f", "32f"):
            with self.subTest(bits=bits):
                self.check("h8.png", heights, {"bits": bits}, ["--bits", bits])

    def test_sixteen_bit_height_with_settings(self):
        heights = height_map(160, 2, np.uint16)
        settings = {"strength": 3.0, "strength_unit": "uv", "wrap": "clamp", "sc": "max",
                    "bake_roughness": 64.0}
        flags = ["--strength", "3", "--strength-unit", "uv", "--wrap", "clamp", "--sc", "max",
                 "--bake-roughness", "64"]
        self.check("h16.png", heights, settings, flags)

    def test_normal_maps_both_conventions(self):
        normals = normal_map(128, 3)
        self.check("n8.png", normals, {}, [])
        directx = normals.copy()
        directx[..., 1] = 255 - directx[..., 1]
        self.check("n8dx.png", directx, {"directx": True}, ["--directx"])
        self.check("n16.png", normal_map(96, 4, np.uint16), {"bits": "16f"}, ["--bits", "16f"])

    def test_plateau_layer_kept_and_dropped(self):
        # Terraces: flat steps between ramps, so the plateau rule finds flat texels.
        terraces = (np.floor(height_map(128, 5).astype(np.float64) / 32) * 32).astype(np.uint8)
        lean = self.check("terraces.png", terraces, {"plateau_epsilon": 0.05},
                          ["--plateau-epsilon", "0.05"])
        self.assertTrue(lean.has_plateau)
        self.assertGreater(lean.summary["plateau_fraction"], 0.0)
        noise = np.random.default_rng(6).integers(0, 256, (128, 128), dtype=np.uint8)
        # Nothing flat, and the plateaus alone form the spike: no layer of zeros stored.
        lean = self.check("noise.png", noise, {"spike": "plateaus"}, ["--spike", "plateaus"])
        self.assertFalse(lean.has_plateau)
        self.assertIsNone(lean.summary["spike_window"])

    def test_png_pair_same_bytes(self):
        source = self.path("h.png")
        leanfade.write_image(source, height_map(64, 7))
        cli_bake(source, "-o", self.path("cli.png"), "--bits", "8")
        leanfade.bake(source, bits="8").save(self.path("py.png"))
        for suffix in (".lean1.png", ".lean2.png"):
            with open(self.path("cli" + suffix), "rb") as a, open(self.path("py" + suffix), "rb") as b:
                self.assertEqual(a.read(), b.read(), suffix)


class Levels(unittest.TestCase):
    def test_views_hold_the_files_texels(self):
        with tempfile.TemporaryDirectory(dir=os.environ.get("LEANFADE_TEST_TMP")) as folder:
            # Uncompressed levels: the test reads the file's level bytes itself.
            lean = leanfade.bake(height_map(100, 8), bits="16", supercompression="none")
            path = os.path.join(folder, "m.ktx2")
            lean.save(path)
            self.assertEqual(leanfade.info(path)["supercompression_scheme"], 0)
            # By default, as `leanfade bake`: Zstandard levels that load as the same texels.
            packed = os.path.join(folder, "z.ktx2")
            zstd = leanfade.bake(height_map(100, 8), bits="16")
            zstd.save(packed)
            self.assertEqual(leanfade.info(packed)["supercompression_scheme"], 2)
            self.assertLess(os.path.getsize(packed), os.path.getsize(path))
            for mine, loaded in zip(zstd.levels, leanfade.load(packed).levels):
                self.assertEqual(mine["lean1"].tobytes(), loaded["lean1"].tobytes())
                self.assertEqual(mine["lean2"].tobytes(), loaded["lean2"].tobytes())
            levels = lean.levels
            self.assertEqual(len(levels), 7)  # 100, 50, 25, 12, 6, 3, 1
            self.assertEqual(lean.summary["levels"], 7)
            for level, entry in enumerate(levels):
                size = max(1, 100 >> level)
                for layer, name in enumerate(("lean1", "lean2", "plateau")):
                    view = entry[name]
                    if name == "plateau" and not lean.has_plateau:
                        self.assertIsNone(view)
                        continue
                    self.assertEqual(view.shape, (size, size, 4))
                    self.assertEqual(view.dtype, np.uint16)
                    self.assertFalse(view.flags.writeable)
                    self.assertEqual(view.tobytes(), ktx2_level_bytes(path, level, layer))
            # The views keep the map alive.
            view = levels[0]["lean2"]
            expected = view.copy()
            del lean, levels, entry
            self.assertTrue(np.array_equal(view, expected))

    def test_moments_filter_linearly(self):
        # Each coarser level of B (lean2.xy, decoded) is the 2x2 mean of the finer one: the
        # moments are linear, within 16-bit rounding.
        lean = leanfade.bake(height_map(64, 9), bits="32f")
        self.assertEqual(lean.encoding, "signed")
        fine = lean.levels[0]["lean2"][..., :2].astype(np.float64) * lean.scale
        coarse = lean.levels[1]["lean2"][..., :2].astype(np.float64) * lean.scale
        filtered = fine.reshape(32, 2, 32, 2, 2).mean(axis=(1, 3))
        self.assertLess(np.abs(filtered - coarse).max(), 1e-6)

    def test_roughness_textures_match_the_cli(self):
        with tempfile.TemporaryDirectory(dir=os.environ.get("LEANFADE_TEST_TMP")) as folder:
            source = os.path.join(folder, "n.png")
            leanfade.write_image(source, normal_map(64, 10))
            rough = os.path.join(folder, "r.ktx2")
            cli_bake(source, "--roughness-out", rough, "--roughness", "0.3")
            textures = leanfade.roughness_textures(source, base_roughness=0.3)
            self.assertEqual(len(textures["metallic_roughness"]), 7)
            for level, image in enumerate(textures["metallic_roughness"]):
                self.assertEqual(image.tobytes(), ktx2_level_bytes(rough, level, 0))
            normal = os.path.join(folder, "r.normal.ktx2")
            for level, image in enumerate(textures["normal"]):
                self.assertEqual(image.tobytes(), ktx2_level_bytes(normal, level, 0))


class Errors(unittest.TestCase):
    def assert_error(self, subject, call, *args, **kwargs):
        with self.assertRaises(leanfade.Error) as raised:
            call(*args, **kwargs)
        self.assertEqual(raised.exception.subject, subject)
        self.assertEqual(str(raised.exception), f"{subject}: {raised.exception.cause}")
        # A setting error names its setting; an error about the input (a file, an array, bytes)
        # names none.
        is_input = os.sep in subject or subject in ("missing.png", "array", "bytes")
        self.assertEqual(raised.exception.kind, "file" if is_input else "setting")
        self.assertEqual(raised.exception.setting, "" if is_input else subject)
        return raised.exception

    def test_bad_inputs_and_settings(self):
        self.assert_error("missing.png", leanfade.bake, "missing.png")
        with tempfile.TemporaryDirectory(dir=os.environ.get("LEANFADE_TEST_TMP")) as folder:
            truncated = os.path.join(folder, "t.png")
            leanfade.write_image(truncated, height_map(64, 11))
            with open(truncated, "r+b") as f:
                f.truncate(100)
            self.assert_error(truncated, leanfade.bake, truncated)
            # An output never replaces its input.
            source = os.path.join(folder, "n.png")
            leanfade.write_image(source, normal_map(32, 12))
            lean = leanfade.bake(source)
            self.assert_error(os.path.join(folder, "m.txt"), lean.save, os.path.join(folder, "m.txt"))
            self.assert_error(source, leanfade.bake, source, strength=2.0)  # a normal map
        self.assert_error("bits", leanfade.bake, height_map(8, 1), bits="12")
        self.assert_error("strength", leanfade.bake, height_map(8, 1), strength=float("nan"))
        self.assert_error("strength", leanfade.bake, height_map(8, 1), strength=0.0)
        self.assert_error("plateau_epsilon", leanfade.bake, height_map(8, 1), plateau_epsilon=-1)
        self.assert_error("spike", leanfade.bake, height_map(8, 1), spike="window")
        self.assert_error("wrap", leanfade.bake, height_map(8, 1), wrap="mirror")
        self.assert_error("colour", leanfade.bake, height_map(8, 1), colour=1)
        self.assert_error("array", leanfade.bake, np.zeros((0, 4), np.uint8))
        self.assert_error("array", leanfade.bake, np.zeros((4, 4, 5), np.uint8))
        self.assert_error("array", leanfade.bake, np.zeros((4, 4), np.int32))
        self.assert_error("array", leanfade.bake, np.full((8, 8), np.nan, np.float32))
        self.assert_error("array", leanfade.bake, np.zeros((40, 40), np.uint8), max_size=32)
        self.assert_error("bytes", leanfade.bake, b"not an image")

    def test_settings_come_from_the_modules_table(self):
        # leanfade.BAKE_SETTINGS is the module's table of settings and defaults (module.cpp).
        self.assertEqual(leanfade.BAKE_SETTINGS, leanfade._leanfade.BAKE_SETTINGS)
        self.assertEqual(leanfade.BAKE_SETTINGS["spike"], "auto")
        self.assertEqual(leanfade.BAKE_SETTINGS["bits"], "auto")
        self.assertIsNone(leanfade.BAKE_SETTINGS["strength"])
        self.assertEqual(len(leanfade.BAKE_SETTINGS), 15)
        # A value of the wrong type or name is refused naming its setting.
        self.assert_error("threads", leanfade.bake, height_map(8, 1), threads="4")
        self.assert_error("directx", leanfade.bake, height_map(8, 1), directx="yes")
        self.assert_error("strength_unit", leanfade.bake, height_map(8, 1), strength_unit="px")
        self.assert_error("sc", leanfade.bake, height_map(8, 1), sc="min")
        self.assert_error("supercompression", leanfade.bake, height_map(8, 1),
                          supercompression="lz4")
        self.assert_error("bits", leanfade.bake, height_map(8, 1), bits=16)

    def test_an_output_never_replaces_its_input(self):
        with tempfile.TemporaryDirectory(dir=os.environ.get("LEANFADE_TEST_TMP")) as folder:
            png = os.path.join(folder, "h.png")
            leanfade.write_image(png, height_map(16, 13))
            alias = os.path.join(folder, "alias.lean1.png")
            os.symlink(png, alias)
            lean_from_alias = leanfade.bake(alias)
            # Saving a PNG pair whose lean1 file is the input itself is refused.
            self.assert_error(alias, lean_from_alias.save, os.path.join(folder, "alias.png"))
            with open(png, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")


class Stubs(unittest.TestCase):
    def test_every_public_name_has_a_stub(self):
        import ast
        stub = os.path.join(os.path.dirname(leanfade.__file__), "_leanfade.pyi")
        with open(stub) as f:
            tree = ast.parse(f.read())
        declared = {node.name for node in tree.body
                    if isinstance(node, (ast.FunctionDef, ast.ClassDef))}
        declared |= {node.target.id for node in tree.body if isinstance(node, ast.AnnAssign)}
        public = {name for name in dir(leanfade._leanfade) if not name.startswith("_")}
        self.assertEqual(public - declared, set())
        for cls in ("LeanMap", "Cache"):
            members = {name for name in dir(getattr(leanfade._leanfade, cls))
                       if not name.startswith("_")}
            node = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == cls)
            stubbed = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
            self.assertEqual(members - stubbed, set(), cls)


class Gil(unittest.TestCase):
    def test_bakes_release_the_gil(self):
        # While one thread is inside a long bake, another gets to run Python: with the GIL held
        # it could run only once the bake returned.
        heights = height_map(3072, 14)
        times = {}

        def bake():
            times["before"] = time.monotonic()
            leanfade.bake(heights, bits="8", threads=1)
            times["after"] = time.monotonic()

        worker = threading.Thread(target=bake)
        worker.start()
        while "before" not in times:
            time.sleep(0.001)
        time.sleep(0.05)
        checked = time.monotonic()
        worker.join()
        duration = times["after"] - times["before"]
        self.assertGreater(duration, 0.2, "the bake is too short to tell")
        self.assertLess(checked - times["before"], 0.5 * duration)


if __name__ == "__main__":
    unittest.main()
