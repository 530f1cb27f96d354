"""`btnav view RUN_DIR [--open]`: replay a run's `recording` in the live page, until Ctrl-C."""

from __future__ import annotations

import time


def view_main(run_dir: str, *, open_browser: bool = False) -> int:
    from ..viz.live.replay import Replay

    replay = Replay(run_dir).start()
    count = len(replay.frames)
    print(f"replay of {run_dir} ({count} frames) at {replay.url} (Ctrl-C to stop)", flush=True)
    if open_browser:
        import webbrowser

        webbrowser.open(replay.url)
    try:
        while True:
            time.sleep(0.5)
    except KeyboardInterrupt:
        pass
    finally:
        replay.close()
    return 0
