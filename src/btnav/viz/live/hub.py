"""The page's server: aiohttp on 127.0.0.1 (a free port), in a thread of its own.

`Hub(on_command)` serves the page's files (package data under `static/`) and one
WebSocket, `/ws`. The sim thread hands it messages with `publish`: a `frame` replaces
any frame a page has not been sent yet (a slow page skips frames, the sim never
waits for it); every other message (map, costmap, tree) is queued and sent in order.
What a page sends (JSON commands) goes to `on_command(command)` on the server's
thread; the live view only queues them there, to apply them in the sim thread.
"""

from __future__ import annotations

import asyncio
import json
import threading
from collections.abc import Callable
from importlib.resources import files
from typing import Any

from ...core.errors import BtnavError

STATIC = files("btnav.viz.live") / "static"
CONTENT_TYPES = {".html": "text/html", ".js": "text/javascript", ".css": "text/css"}


def _aiohttp() -> Any:
    try:
        from aiohttp import web
    except ImportError:
        raise BtnavError(
            "the live view needs aiohttp, which comes with the view extra: "
            "pip install 'btnav[view]'"
        ) from None
    return web


class _Client:
    def __init__(self, ws: Any) -> None:
        self.ws = ws
        self.queue: list[str] = []
        self.frame: str | None = None
        self.wake = asyncio.Event()


class Hub:
    """Serves the page and its WebSocket from a daemon thread (see the module doc)."""

    def __init__(
        self, on_command: Callable[[dict[str, Any]], None], host: str = "127.0.0.1"
    ) -> None:
        self.web = _aiohttp()
        self.on_command = on_command
        self.host = host
        self.port = 0
        self.clients: set[_Client] = set()
        self.loop = asyncio.new_event_loop()
        self._started = threading.Event()
        self._runner: Any = None
        self._thread = threading.Thread(target=self._serve, name="btnav-view", daemon=True)

    @property
    def url(self) -> str:
        return f"http://{self.host}:{self.port}/"

    @property
    def connected(self) -> int:
        return len(self.clients)

    def start(self) -> Hub:
        self._thread.start()
        self._started.wait(10.0)
        if not self.port:
            raise BtnavError(f"the live view could not listen on {self.host}")
        return self

    def stop(self) -> None:
        if self._thread.is_alive():
            asyncio.run_coroutine_threadsafe(self._shutdown(), self.loop).result(5.0)
            self.loop.call_soon_threadsafe(self.loop.stop)
            self._thread.join(5.0)

    def publish(self, message: dict[str, Any]) -> None:
        """Send `message` to every page (from any thread)."""
        if self.clients:
            text = json.dumps(message, separators=(",", ":"))
            self.loop.call_soon_threadsafe(self._put, text, message.get("type") == "frame")

    # -- the server's thread ------------------------------------------------------------

    def _serve(self) -> None:
        asyncio.set_event_loop(self.loop)
        try:
            self.loop.run_until_complete(self._listen())
        finally:
            self._started.set()
        self.loop.run_forever()

    async def _listen(self) -> None:
        web = self.web
        app = web.Application()
        app.router.add_get("/", self._file)
        app.router.add_get("/ws", self._socket)
        app.router.add_get("/static/{name}", self._file)
        app.router.add_get("/favicon.ico", self._no_content)
        self._runner = web.AppRunner(app, access_log=None)
        await self._runner.setup()
        site = web.TCPSite(self._runner, self.host, 0)
        await site.start()
        self.port = site._server.sockets[0].getsockname()[1]

    async def _shutdown(self) -> None:
        for client in list(self.clients):
            await client.ws.close()
        if self._runner is not None:
            await self._runner.cleanup()

    async def _no_content(self, request: Any) -> Any:
        return self.web.Response(status=204)

    async def _file(self, request: Any) -> Any:
        name = request.match_info.get("name", "index.html")
        path = STATIC / name
        suffix = "." + name.rsplit(".", 1)[-1]
        if "/" in name or suffix not in CONTENT_TYPES or not path.is_file():
            raise self.web.HTTPNotFound()
        return self.web.Response(text=path.read_text("utf-8"), content_type=CONTENT_TYPES[suffix])

    async def _socket(self, request: Any) -> Any:
        ws = self.web.WebSocketResponse(heartbeat=20.0)
        await ws.prepare(request)
        client = _Client(ws)
        self.clients.add(client)
        sender = asyncio.ensure_future(self._send(client))
        self.on_command({"cmd": "hello"})
        try:
            async for msg in ws:
                if msg.type == self.web.WSMsgType.TEXT:
                    try:
                        command = json.loads(msg.data)
                    except ValueError:
                        continue
                    if isinstance(command, dict):
                        self.on_command(command)
        finally:
            self.clients.discard(client)
            sender.cancel()
        return ws

    def _put(self, text: str, droppable: bool) -> None:
        for client in self.clients:
            if droppable:
                client.frame = text
            else:
                client.queue.append(text)
            client.wake.set()

    async def _send(self, client: _Client) -> None:
        while not client.ws.closed:
            await client.wake.wait()
            client.wake.clear()
            while client.queue:
                await client.ws.send_str(client.queue.pop(0))
            if client.frame is not None:
                text, client.frame = client.frame, None
                await client.ws.send_str(text)
