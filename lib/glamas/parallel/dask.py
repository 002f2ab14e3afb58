"""Jobs on a Dask distributed cluster: reaching its scheduler with a deadline, and failing clearly
when its scheduler or workers are lost or absent (optional extra ``dask``)."""

import asyncio
import contextlib
import logging
import time
from concurrent.futures import CancelledError, ThreadPoolExecutor

from glamas.errors import UserError
from glamas.parallel.backends import BackendError, Dask, require_dask
from glamas.parallel.job import batch_chunk, run_chunk

POLL_SECONDS = 0.05
"""How often a wait on a Dask cluster looks for finished jobs and whether it still has workers."""


def connect(backend: Dask):
    """A Dask client of the backend's scheduler (close it after use), or a clear error within
    about ``backend.timeout`` seconds: a malformed address, nothing listening, or a server that
    is not a Dask scheduler."""
    distributed = require_dask()
    failure = f"cannot reach the Dask scheduler at {backend.scheduler} within {backend.timeout:g} s"
    advice = "check the address, or start a scheduler with `dask scheduler` and workers with `dask worker ADDRESS`"
    try:
        with ThreadPoolExecutor(1) as thread:  # its own event loop: the caller may be running one (Jupyter)
            thread.submit(asyncio.run, _probe(distributed, backend)).result()
        return distributed.Client(backend.scheduler, timeout=backend.timeout, set_as_default=False)
    except ConnectionRefusedError:
        raise BackendError(f"{failure} (connection refused: nothing listens there); {advice}") from None
    except (OSError, TimeoutError, asyncio.TimeoutError) as error:
        raise BackendError(f"{failure} ({str(error) or 'no answer'}); {advice}") from None
    except ValueError as error:
        raise BackendError(f"{backend.scheduler!r} is not a Dask scheduler address ({error}); "
                           "give one such as tcp://HOST:8786") from None


async def _probe(distributed, backend: Dask) -> None:
    """Ask the address for its identity, with a deadline: distributed's own client waits without
    one for a server that accepts the connection but never answers as a scheduler would."""
    async def identity():
        await _listening(distributed, backend)
        comm = await distributed.comm.connect(backend.scheduler, timeout=backend.timeout)
        try:
            await comm.write({"op": "identity"})
            return await comm.read()
        finally:
            comm.abort()

    reply = await asyncio.wait_for(identity(), backend.timeout)
    if not (isinstance(reply, dict) and reply.get("type") == "Scheduler"):
        raise OSError(f"the server there answered, but not as a Dask scheduler ({str(reply)[:80]})")


LARGEST_MESSAGE = 2 ** 30
"""Bytes beyond any handshake a Dask scheduler sends: a server whose first 8 bytes read as a length
beyond it speaks another protocol (distributed would try to allocate that much)."""


async def _listening(distributed, backend: Dask) -> None:
    """Connect to the backend's address and read the handshake a Dask scheduler sends as soon as it
    accepts a connection, sending nothing: ConnectionRefusedError at once when nothing listens
    there, where distributed's connect would retry until its timeout; TimeoutError when the server
    accepts but sends nothing (an HTTP server waits for a request); OSError when its first bytes are
    not the length of a Dask message (another protocol's banner). A port out of range is a
    UserError (a ValueError); an address without host and port (``inproc://``) or a malformed one is left to
    distributed's connect."""
    try:
        host, port = distributed.comm.get_address_host_port(backend.scheduler)
    except ValueError:
        return
    if not 0 < port < 2 ** 16:
        raise UserError(f"port {port} is out of range 1-65535")
    reader, writer = await asyncio.open_connection(host, port)
    try:
        try:
            head = await asyncio.wait_for(reader.readexactly(8), backend.timeout / 2)  # within the probe's deadline
        except (asyncio.TimeoutError, asyncio.IncompleteReadError):
            raise TimeoutError("it accepted the connection but sent no Dask handshake") from None
        if int.from_bytes(head, "little") >= LARGEST_MESSAGE:
            raise OSError(f"the server there does not speak Dask's protocol (it began with {head!r})")
    finally:
        writer.close()


def run_on_dask(backend: Dask, jobs: list):
    distributed = require_dask()
    with _client_log_quiet(), connect(backend) as client:
        futures = [client.submit(batch_chunk, k, run_chunk, *job, pure=False) for k, *job in jobs]
        finished = distributed.as_completed(futures, loop=client.loop)
        without_workers = None  # since when the cluster has had no worker
        while not finished.is_empty():
            batch = finished.next_batch(block=False)
            if not batch:  # nothing new: look whether anyone is still working, then wait a little
                without_workers = _check_workers(client, backend, without_workers, finished.count())
                time.sleep(POLL_SECONDS)
            for future in batch:
                yield _result(distributed, future, backend)


@contextlib.contextmanager
def _client_log_quiet():
    """distributed's client logs the traceback of each failed attempt to reach a lost scheduler;
    the run's BackendError says what happened, in one line."""
    logger = logging.getLogger("distributed.client")
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        logger.setLevel(level)


def _check_workers(client, backend: Dask, without_workers, n_pending: int):
    """When the cluster has no workers left, raise after ``backend.timeout`` seconds; returns
    since when it has had none (None: it has workers)."""
    if client.scheduler_info().get("workers"):
        return None
    now = time.monotonic()
    if without_workers is not None and now - without_workers > backend.timeout:
        raise BackendError(f"the Dask cluster at {backend.scheduler} has had no worker for "
                           f"{backend.timeout:g} s with {n_pending} jobs left (a worker was lost or none "
                           "was started); start workers with `dask worker ADDRESS`")
    return now if without_workers is None else without_workers


def _result(distributed, future, backend: Dask):
    try:
        return future.result()
    except distributed.KilledWorker as error:
        raise BackendError(f"a job was lost with the Dask workers that ran it ({error}); check the "
                           "workers' memory and logs, then run again") from None
    except CancelledError as error:  # the client cancels every job when it loses the scheduler
        reason = getattr(error, "reason", None) or "its job was cancelled"
        raise BackendError(f"the Dask scheduler at {backend.scheduler} was lost mid-run ({reason}); check that "
                           "it runs and answers, then run again") from None
