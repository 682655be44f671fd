"""python3 -m leanfade.batch MANIFEST.jsonl: bake many maps on a Dask cluster (docs/pipelines.md).

MANIFEST.jsonl holds one job per line, a JSON object:

    {"input": "maps/bricks_n.png", "output": "lean/bricks_n.ktx2", "settings": {"bits": "16"}}

input: a height or normal map (what `leanfade bake` reads); output: the LEAN map, a .ktx2 file;
settings: `leanfade bake`'s flags without the dashes (leanfade.BAKE_SETTINGS), optional. Relative
paths are taken from the manifest's folder, and every input and output must resolve inside the
root (--root, default that folder). Blank lines and lines starting with '#' are skipped.

Each job is keyed by the SHA-256 of its input's bytes and of every setting (leanfade.cache_key,
the key of leanfade's cache): a job whose output already holds what its cache record says is
"done" and skipped; one whose result is in the cache folder is copied from it ("cached", after
checking its SHA-256); the others are baked ("baked") and stored in the cache. Outputs and cache
entries are hard links of one another where they share a file system (no byte copied), else
copies. The cache is asked first, by this process: a rerun of an unchanged manifest starts no
cluster. Every output
appears whole or not at all (written to a temporary file and renamed). The cache folder may be
shared between machines (NFS): its entries are written the same way and verified when served.

Without --scheduler the jobs run on a local Dask cluster of --workers processes; with
--scheduler tcp://HOST:PORT (or --scheduler-file) on that cluster, whose workers must import
leanfade and see the same paths. A worker that dies mid-job has its jobs run again elsewhere.
--job N runs line N (1-based) alone in this process, without Dask: for GNU parallel and Slurm
array jobs. Exit status: 0, 1 when a job failed, 2 for a manifest or flag that cannot be used.
"""
from __future__ import annotations

import argparse
import functools
import json
import os
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional

import leanfade

PROGRAM = "leanfade batch"
RECORD_SUFFIX = ".batch.json"
RECORDS_FOLDER = "batch-records"
DEFAULT_CACHE_BYTES = 2 << 30  # leanfade's cache bound (kMaxLeanCacheBytes)
OUTPUT_SUFFIX = ".batch.ktx2"
JOB_FIELDS = {"input", "output", "settings"}


class ManifestError(Exception):
    """A manifest or a flag that cannot be used: nothing runs."""


@dataclass
class Job:
    line: int
    input: str
    output: str
    settings: dict[str, Any] = field(default_factory=dict)
    settings_text: str = ""


def _confined(root: Path, base: Path, text: Any, where: str, what: str) -> str:
    if not isinstance(text, str) or not text:
        raise ManifestError(f"{where}: '{what}' must be a non-empty path")
    if "\0" in text:
        raise ManifestError(f"{where}: '{what}' holds a NUL character")
    resolved = (base / text).resolve()
    if resolved != root and root not in resolved.parents:
        raise ManifestError(f"{where}: {what} '{text}' resolves to {resolved}, outside the root "
                            f"{root} (--root)")
    return str(resolved)


def read_manifest(path: str, root: Optional[str] = None) -> list[Job]:
    """The jobs of a manifest, every line checked (ManifestError naming MANIFEST:LINE)."""
    manifest = Path(path)
    try:
        text = manifest.read_bytes().decode("utf-8")
    except OSError as e:
        raise ManifestError(f"{path}: cannot read ({e.strerror or e})") from None
    except UnicodeDecodeError:
        raise ManifestError(f"{path}: not UTF-8 text") from None
    base = manifest.resolve().parent
    confine = Path(root).resolve() if root else base
    jobs: list[Job] = []
    outputs: dict[str, int] = {}
    for number, line in enumerate(text.splitlines(), start=1):
        where = f"{path}:{number}"
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            entry = json.loads(line)
        except json.JSONDecodeError as e:
            raise ManifestError(f"{where}: not JSON ({e.msg} at column {e.colno})") from None
        if not isinstance(entry, dict):
            raise ManifestError(f"{where}: expected a JSON object")
        unknown = sorted(set(entry) - JOB_FIELDS)
        if unknown:
            raise ManifestError(f"{where}: unknown field '{unknown[0]}' (expected input, output, "
                                "settings)")
        settings = entry.get("settings", {})
        if not isinstance(settings, dict):
            raise ManifestError(f"{where}: 'settings' must be a JSON object")
        try:
            settings_text = leanfade.settings_text(**settings)
        except leanfade.Error as e:
            raise ManifestError(f"{where}: settings: {e}") from None
        job = Job(number, _confined(confine, base, entry.get("input"), where, "input"),
                  _confined(confine, base, entry.get("output"), where, "output"), settings,
                  settings_text)
        if not job.output.lower().endswith(".ktx2"):
            raise ManifestError(f"{where}: output '{entry['output']}' is not a .ktx2 file")
        if job.output in outputs:
            raise ManifestError(f"{where}: output '{entry['output']}' is also the output of line "
                                f"{outputs[job.output]}")
        outputs[job.output] = number
        jobs.append(job)
    inputs = {job.input: job.line for job in jobs}
    for job in jobs:
        if job.output in inputs:
            raise ManifestError(f"{path}:{job.line}: output '{job.output}' is the input of line "
                                f"{inputs[job.output]}; an output may not replace an input")
    if not jobs:
        raise ManifestError(f"{path}: no job")
    return jobs


def _output_holds(path: str, record: dict[str, Any]) -> bool:
    try:
        if os.path.getsize(path) != record["size"]:
            return False
        return leanfade.sha256_file(path) == record["sha256"]
    except (OSError, leanfade.Error):
        return False


def _job_key(job: Job, data: bytes) -> str:
    return leanfade.cache_key([data], f"batch ktx2 {job.settings_text}")


def _read_input(job: Job) -> bytes:
    try:
        return Path(job.input).read_bytes()
    except OSError as e:
        raise leanfade.Error(f"{job.input}: cannot read ({e.strerror or e})") from None


@functools.lru_cache(maxsize=None)
def _caches(folder: str, max_bytes: int) -> tuple[leanfade.Cache, leanfade.Cache]:
    """The cache folder's outputs (at most max_bytes, the oldest removed first), and its records
    (a subfolder, so that evicting large outputs never forgets which outputs are done), once per
    process."""
    return (leanfade.Cache(folder, max_bytes),
            leanfade.Cache(os.path.join(folder, RECORDS_FOLDER)))


def _record(records: leanfade.Cache, key: str) -> Optional[dict[str, Any]]:
    stored = records.find_file(key, RECORD_SUFFIX)
    try:
        record = json.loads(stored) if stored is not None else None
    except ValueError:
        return None  # a damaged record is a miss, replaced by the next bake
    if not (isinstance(record, dict) and isinstance(record.get("size"), int)
            and isinstance(record.get("sha256"), str)):
        return None
    return record


def _served(job: Job, cache_folder: str, cache_bytes: int, key: str) -> Optional[str]:
    """"done" when the output holds the bytes its record names, "cached" when the cache entry
    was put there (its SHA-256 checked), else None."""
    outputs, records = _caches(cache_folder, cache_bytes)
    record = _record(records, key)
    if record is None:
        return None
    if _output_holds(job.output, record):
        return "done"
    if outputs.serve_file_to(key, OUTPUT_SUFFIX, record["size"], record["sha256"], job.output):
        return "cached"
    return None


def _result(job: Job, status: str, start: Optional[float], error: Optional[str] = None
            ) -> dict[str, Any]:
    """A job's result: its line, input, output and status, the error of a failed one, and the
    seconds since `start` (none when the job was lost with its worker)."""
    result: dict[str, Any] = {"line": job.line, "input": job.input, "output": job.output,
                              "status": status}
    if error is not None:
        result["error"] = error
    if start is not None:
        result["seconds"] = time.monotonic() - start
    return result


def serve_job(job: Job, cache_folder: str,
              cache_bytes: int = DEFAULT_CACHE_BYTES) -> Optional[dict[str, Any]]:
    """The job's result when the cache serves it ("done" or "cached"), without baking; None when
    it must be baked. Run for every job before the cluster is asked for anything, so that a rerun
    of an unchanged manifest needs no worker."""
    start = time.monotonic()
    try:
        status = _served(job, cache_folder, cache_bytes, _job_key(job, _read_input(job)))
    except leanfade.Error:
        return None  # reported by the bake, where it runs
    return None if status is None else _result(job, status, start)


def run_job(job: Job, cache_folder: Optional[str],
            cache_bytes: int = DEFAULT_CACHE_BYTES) -> dict[str, Any]:
    """One job, where it runs (a Dask worker or this process): {"line", "input", "output",
    "status": "done" | "cached" | "baked" | "failed", "error" (failed only), "seconds"}."""
    start = time.monotonic()
    try:
        data = _read_input(job)
        key = _job_key(job, data)
        status = _served(job, cache_folder, cache_bytes, key) if cache_folder else None
        if status is None:
            lean = leanfade.bake(data, name=job.input, **job.settings)
            lean.save(job.output)
            status = "baked"
            if cache_folder:
                outputs, records = _caches(cache_folder, cache_bytes)
                size = os.path.getsize(job.output)
                sha256 = leanfade.sha256_file(job.output)
                # The output by a hard link (no copy where the cache shares its file system),
                # then its record: an entry counts once its record is there.
                outputs.store_file_link(key, OUTPUT_SUFFIX, job.output, size)
                records.store_file(key, RECORD_SUFFIX,
                                   json.dumps({"size": size, "sha256": sha256}).encode())
    except leanfade.Error as e:
        return _result(job, "failed", start, str(e))
    except Exception as e:  # anything else is this job's failure too, not the batch's
        return _result(job, "failed", start, f"{job.input}: {type(e).__name__}: {e}")
    return _result(job, status, start)


class Progress:
    """A status line on a terminal (stderr), nothing otherwise."""

    def __init__(self, total: int) -> None:
        self.total = total
        self.counts = {"done": 0, "cached": 0, "baked": 0, "failed": 0}
        self.shown = sys.stderr.isatty()

    def add(self, result: dict[str, Any]) -> None:
        self.counts[result["status"]] += 1
        if self.shown:
            finished = sum(self.counts.values())
            sys.stderr.write(f"\r[{finished}/{self.total}] {self.counts['baked']} baked, "
                             f"{self.counts['cached']} cached, {self.counts['done']} done, "
                             f"{self.counts['failed']} failed\033[K")
            sys.stderr.flush()

    def close(self) -> None:
        if self.shown:
            sys.stderr.write("\r\033[K")


def run_on_dask(jobs: list[Job], cache_folder: Optional[str], cache_bytes: int,
                scheduler: Optional[str],
                scheduler_file: Optional[str], workers: int, progress: Progress) -> list[dict]:
    from distributed import Client, LocalCluster, as_completed

    cluster = None
    if scheduler or scheduler_file:
        client = Client(scheduler_file=scheduler_file) if scheduler_file else Client(scheduler)
    else:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    try:
        futures = client.map(run_job, jobs, cache_folder=cache_folder, cache_bytes=cache_bytes,
                             pure=False)
        by_future = dict(zip(futures, jobs))
        results = []
        for future in as_completed(futures):
            try:
                result = future.result()
            except Exception as e:  # e.g. KilledWorker: the job killed every worker it ran on
                job = by_future[future]
                result = _result(job, "failed", None, f"{job.input}: {type(e).__name__}: {e}")
            progress.add(result)
            results.append(result)
        return results
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def main(argv: Optional[list[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python3 -m leanfade.batch",
        description="Bake the jobs of a manifest (one JSON object per line) on a Dask cluster.")
    parser.add_argument("manifest", help="MANIFEST.jsonl")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="tcp://HOST:PORT of a running Dask scheduler")
    where.add_argument("--scheduler-file", help="a Dask scheduler file (dask-scheduler "
                       "--scheduler-file)")
    where.add_argument("--job", type=int, metavar="N",
                       help="run only line N (1-based) here, without Dask (GNU parallel, Slurm)")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="processes of the local cluster (default: the cores)")
    parser.add_argument("--cache", default=None,
                        help="cache folder, shared by every worker (default: leanfade's, "
                        "$XDG_CACHE_HOME/leanfade)")
    parser.add_argument("--cache-gib", type=float, default=DEFAULT_CACHE_BYTES / 2**30,
                        help="bound of the cache folder's outputs in GiB, the oldest removed "
                        "first (default 2, leanfade's; outputs hard-linked from it take no "
                        "space of their own)")
    parser.add_argument("--no-cache", action="store_true", help="bake every job")
    parser.add_argument("--root", default=None,
                        help="inputs and outputs must resolve inside this folder (default: the "
                        "manifest's)")
    parser.add_argument("--json", default=None, help="also write each job's result as JSON")
    args = parser.parse_args(argv)
    started = time.monotonic()
    try:
        if args.workers < 1:
            raise ManifestError("--workers: must be at least 1")
        if not (0 < args.cache_gib < 2**20):
            raise ManifestError("--cache-gib: must be a positive number of GiB")
        cache_bytes = int(args.cache_gib * 2**30)
        jobs = read_manifest(args.manifest, args.root)
        if args.job is not None:
            chosen = [job for job in jobs if job.line == args.job]
            if not chosen:
                raise ManifestError(f"--job: line {args.job} of {args.manifest} holds no job")
            jobs = chosen
        if args.json and any(os.path.realpath(args.json) in (job.input, job.output)
                             for job in jobs) or (args.json and os.path.realpath(args.json) ==
                                                  os.path.realpath(args.manifest)):
            raise ManifestError(f"--json: '{args.json}' is an input or output of the batch")
        cache = None if args.no_cache else (args.cache or leanfade.default_cache_folder() or None)
        if cache:
            cache = str(Path(cache).resolve())
    except ManifestError as e:
        print(f"{PROGRAM}: {e}", file=sys.stderr)
        return 2
    progress = Progress(len(jobs))
    results: list[dict[str, Any]] = []
    if cache:
        # What the cache serves first, here, on threads (hashing and copying release the GIL).
        with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
            served = list(pool.map(lambda job: serve_job(job, cache, cache_bytes), jobs))
        for result in served:
            if result is not None:
                progress.add(result)
                results.append(result)
        jobs = [job for job, result in zip(jobs, served) if result is None]
    if args.job is not None or len(jobs) == 0:
        for job in jobs:
            results.append(run_job(job, cache, cache_bytes))
            progress.add(results[-1])
    else:
        results += run_on_dask(jobs, cache, cache_bytes, args.scheduler, args.scheduler_file,
                               args.workers, progress)
    progress.close()
    results.sort(key=lambda r: r["line"])
    for result in results:
        if result["status"] == "failed":
            print(f"{PROGRAM}: {result['error']}", file=sys.stderr)
    counts = progress.counts
    print(f"{PROGRAM}: {len(results)} jobs in {time.monotonic() - started:.1f} s: "
          f"{counts['baked']} baked, {counts['cached']} from the cache, {counts['done']} already "
          f"done, {counts['failed']} failed")
    if args.json:
        temporary = f"{args.json}.tmp{os.getpid()}"
        with open(temporary, "w", encoding="utf-8") as out:
            json.dump(results, out, indent=2)
            out.write("\n")
        os.replace(temporary, args.json)
    return 1 if counts["failed"] else 0


if __name__ == "__main__":
    # The jobs and run_job must be pickled as leanfade.batch's, which the workers import, not
    # as __main__'s.
    from leanfade.batch import main as batch_main

    sys.exit(batch_main())
