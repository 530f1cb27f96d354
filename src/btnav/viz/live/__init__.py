"""The browser view of a run: live (`btnav run --view`) and replayed (`btnav view RUN_DIR`).

`messages` turns a run's state into the JSON the page draws, `hub` serves the page and
its WebSocket (aiohttp, in a thread of its own), `live_view` is the MONITOR component
that paces the sim and applies the user's clicks, `recording` writes and reads the
`recording` output the replay shows.
"""
