"""python3 -m leanfade.batch on a Dask cluster on 127.0.0.1: a scheduler and two workers, one of
them killed mid-run; every output byte-identical to `leanfade bake`'s; a rerun from the cache."""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

import leanfade

LEANFADE = os.environ["LEANFADE_EXE"]
MAPS = 22
SIZE = 1024


def maps(folder):
    """MAPS inputs, 8- and 16-bit, height and normal maps (both conventions), and the settings
    of each job."""
    rng = np.random.default_rng(20)
    jobs = []
    y, x = np.mgrid[0:SIZE, 0:SIZE] / SIZE
    for i in range(MAPS):
        h = 0.5 + 0.2 * np.sin(2 * np.pi * (i % 5 + 1) * x + i) * np.cos(2 * np.pi * 3 * y)
        h = h + 0.05 * rng.random((SIZE, SIZE))
        settings = {}
        if i % 3 == 2:  # a normal map
            gy, gx = np.gradient(h * 60)
            n = np.stack([-gx, gy, np.ones_like(h)], axis=-1)
            n /= np.linalg.norm(n, axis=-1, keepdims=True)
            if i % 2:
                n[..., 1] = -n[..., 1]
                settings["directx"] = True
            image = np.round((0.5 * n + 0.5) * 255).astype(np.uint8)
        elif i % 3 == 1:
            image = np.round(h * 65535).astype(np.uint16)
            settings["strength"] = 4.0
        else:
            image = np.round(h * 255).astype(np.uint8)
        settings["bits"] = ("auto", "16", "8", "16f")[i % 4]
        name = f"map{i:02d}.png"
        leanfade.write_image(os.path.join(folder, "in", name), image)
        jobs.append({"input": f"in/{name}", "output": f"out/map{i:02d}.ktx2",
                     "settings": settings})
    return jobs


def flags(settings):
    out = []
    for name, value in settings.items():
        flag = "--" + name.replace("_", "-")
        out += [flag] if value is True else [flag, str(value)]
    return out


class DaskBatch(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory(dir=os.environ.get("LEANFADE_TEST_TMP"))
        self.dir = self.tmp.name
        for sub in ("in", "out", "reference", "cache"):
            os.makedirs(os.path.join(self.dir, sub))
        self.processes = []
        self.logs = []

    def tearDown(self):
        for process in self.processes:
            if process.poll() is None:
                process.kill()
            process.wait()
        for log in self.logs:
            log.close()
        self.tmp.cleanup()

    def start(self, *command):
        log = open(os.path.join(self.dir, f"log{len(self.processes)}.txt"), "w")
        self.logs.append(log)
        process = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT,
                                   start_new_session=True)
        self.processes.append(process)
        return process

    def cluster(self):
        """A scheduler on 127.0.0.1 (a free port) and two single-thread workers without a
        nanny, so that killing one kills its jobs."""
        scheduler_file = os.path.join(self.dir, "scheduler.json")
        self.start(sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                   "--port", "0", "--no-dashboard", "--scheduler-file", scheduler_file)
        workers = [self.start(sys.executable, "-m", "distributed.cli.dask_worker",
                              "--scheduler-file", scheduler_file, "--host", "127.0.0.1",
                              "--nthreads", "1", "--no-nanny", "--no-dashboard",
                              "--name", f"worker{i}") for i in range(2)]
        deadline = time.monotonic() + 60
        while not os.path.exists(scheduler_file) and time.monotonic() < deadline:
            time.sleep(0.1)
        from distributed import Client
        with Client(scheduler_file=scheduler_file, timeout=60) as client:
            client.wait_for_workers(2, timeout=60)
        return scheduler_file, workers

    def batch(self, manifest, scheduler_file, *extra):
        return subprocess.Popen(
            [sys.executable, "-m", "leanfade.batch", manifest, "--scheduler-file", scheduler_file,
             "--cache", os.path.join(self.dir, "cache"), "--json",
             os.path.join(self.dir, "results.json"), *extra],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def outputs_done(self, jobs):
        return sum(os.path.exists(os.path.join(self.dir, job["output"])) for job in jobs)

    def test_killed_worker_outputs_and_cache(self):
        jobs = maps(self.dir)
        manifest = os.path.join(self.dir, "manifest.jsonl")
        with open(manifest, "w") as f:
            for job in jobs:
                f.write(json.dumps(job) + "\n")
        for job in jobs:
            subprocess.run([LEANFADE, "bake", os.path.join(self.dir, job["input"]), "-o",
                            os.path.join(self.dir, "reference", os.path.basename(job["output"])),
                            *flags(job["settings"])], check=True, capture_output=True)
        scheduler_file, workers = self.cluster()

        # First run: one worker is killed once two outputs are there.
        start = time.monotonic()
        run = self.batch(manifest, scheduler_file)
        while self.outputs_done(jobs) < 2 and run.poll() is None:
            time.sleep(0.02)
        done_at_kill = self.outputs_done(jobs)
        os.killpg(workers[0].pid, signal.SIGKILL)
        workers[0].wait()
        stdout, stderr = run.communicate(timeout=240)
        first = time.monotonic() - start
        print(f"\nfirst run {first:.2f} s (worker killed after {done_at_kill} of {MAPS} outputs)"
              f": {stdout.strip()}", file=sys.stderr)
        self.assertEqual(run.returncode, 0, stderr)
        self.assertLess(done_at_kill, MAPS, "the worker was killed after the run")
        self.assertIn(f"{MAPS} jobs", stdout)
        with open(os.path.join(self.dir, "results.json")) as f:
            results = json.load(f)
        # Every job baked; the one the killed worker (one thread) had in hand may have written
        # its output before the kill: run again elsewhere, it finds that output complete and
        # reports it "done" (the kill races with the write).
        statuses = sorted(r["status"] for r in results)
        self.assertEqual(len(statuses), MAPS)
        self.assertLessEqual(set(statuses), {"baked", "done"}, statuses)
        self.assertLessEqual(statuses.count("done"), 1, statuses)
        self.assert_outputs_match(jobs)

        # Second run, outputs removed: every one served from the cache.
        for job in jobs:
            os.remove(os.path.join(self.dir, job["output"]))
        start = time.monotonic()
        run = self.batch(manifest, scheduler_file)
        stdout, stderr = run.communicate(timeout=240)
        second = time.monotonic() - start
        print(f"second run {second:.2f} s: {stdout.strip()}", file=sys.stderr)
        self.assertEqual(run.returncode, 0, stderr)
        self.assertIn(f"0 baked, {MAPS} from the cache", stdout)
        self.assert_outputs_match(jobs)
        self.assertLess(second, first / 3)

        # Third run: everything done.
        run = self.batch(manifest, scheduler_file)
        stdout, _ = run.communicate(timeout=240)
        self.assertIn(f"0 baked, 0 from the cache, {MAPS} already done", stdout)

        # A damaged cache entry (replaced, as a broken copy on a shared folder would be) is not
        # served: its job is baked again.
        os.remove(os.path.join(self.dir, jobs[0]["output"]))
        cache = os.path.join(self.dir, "cache")
        for entry in os.listdir(cache):
            if entry.endswith(".batch.ktx2"):
                with open(os.path.join(cache, entry), "rb") as f:
                    data = bytearray(f.read())
                data[300:302] = b"\xff\xfe"
                with open(os.path.join(cache, entry + ".new"), "wb") as f:
                    f.write(data)
                os.replace(os.path.join(cache, entry + ".new"), os.path.join(cache, entry))
        run = self.batch(manifest, scheduler_file)
        stdout, _ = run.communicate(timeout=240)
        self.assertIn(f"1 baked, 0 from the cache, {MAPS - 1} already done", stdout)
        self.assert_outputs_match(jobs)

        # An output changed in place is not "done": it is baked again (or served from an
        # intact cache entry).
        with open(os.path.join(self.dir, jobs[1]["output"]), "r+b") as f:
            f.seek(400)
            f.write(b"\x00\x01")
        run = self.batch(manifest, scheduler_file)
        stdout, _ = run.communicate(timeout=240)
        self.assertIn(f"{MAPS - 1} already done", stdout)
        self.assert_outputs_match(jobs)

    def assert_outputs_match(self, jobs):
        for job in jobs:
            name = os.path.basename(job["output"])
            with open(os.path.join(self.dir, job["output"]), "rb") as a, \
                    open(os.path.join(self.dir, "reference", name), "rb") as b:
                self.assertEqual(a.read(), b.read(), name)

    def test_failed_job_and_bad_manifest(self):
        folder = self.dir
        leanfade.write_image(os.path.join(folder, "in", "good.png"),
                             np.random.default_rng(1).integers(0, 255, (64, 64), dtype=np.uint8))
        with open(os.path.join(folder, "in", "bad.png"), "wb") as f:
            f.write(b"\x89PNG\r\n\x1a\n truncated")
        manifest = os.path.join(folder, "m.jsonl")
        with open(manifest, "w") as f:
            f.write(json.dumps({"input": "in/good.png", "output": "out/good.ktx2"}) + "\n")
            f.write(json.dumps({"input": "in/bad.png", "output": "out/bad.ktx2"}) + "\n")
        env = dict(os.environ)
        for line, (status, expect) in enumerate(((0, "1 baked"), (1, "bad.png")), start=1):
            run = subprocess.run([sys.executable, "-m", "leanfade.batch", manifest, "--job",
                                  str(line), "--no-cache"], capture_output=True, text=True, env=env)
            self.assertEqual(run.returncode, status, run.stderr)
            self.assertIn(expect, run.stdout + run.stderr)
        self.assertFalse(os.path.exists(os.path.join(folder, "out", "bad.ktx2")))
        bad_lines = [
            ("{not json", "not JSON"),
            (json.dumps({"input": "in/good.png", "output": "../escape.ktx2"}), "outside the root"),
            (json.dumps({"input": "in/good.png", "output": "in/good.png"}), "not a .ktx2"),
            (json.dumps({"input": "in/good.png", "output": "o.ktx2", "settings": {"bits": "9"}}),
             "bits"),
            (json.dumps({"input": "in/good.png", "output": "o.ktx2", "extra": 1}), "unknown field"),
        ]
        for text, expect in bad_lines:
            with open(manifest, "w") as f:
                f.write(text + "\n")
            run = subprocess.run([sys.executable, "-m", "leanfade.batch", manifest, "--no-cache"],
                                 capture_output=True, text=True, env=env)
            self.assertEqual(run.returncode, 2, text)
            self.assertIn(f"{manifest}:1: ", run.stderr)
            self.assertIn(expect, run.stderr)
            self.assertEqual(len(run.stderr.strip().splitlines()), 1, run.stderr)


if __name__ == "__main__":
    unittest.main()
