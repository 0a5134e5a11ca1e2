"""Peer solvers, each run as ``python -m benchmarks.peers.<name>`` by :func:`benchmarks.common.run_peer`.

Never import these modules into a process that has imported highspy (parcover, milp).
"""
