"""``dembridge-mbdyn-testpeer``: the MBDyn test peer, a stand-in for MBDyn's ``external structural``
and ``external modal`` sides (rigid nodes, hinges, modal bodies) for running the MBDyn examples and
the coupled demo without MBDyn. Every argument goes to the peer; ``--help`` lists them.

    dembridge-mbdyn-testpeer --path mbdyn.sock --nodes 1 --orientation none --steps 500 --dt 0.004 ...

pip installs the peer inside this package (``dembridge/bin/mbdyn_testpeer``); this command execs it.
"""
import os
import sys

from .locate import built_testpeer


def main():
    peer = built_testpeer()  # never the command itself found on PATH: that would exec this again
    if not os.access(peer, os.X_OK):
        sys.exit(f"dembridge-mbdyn-testpeer: no test peer at {peer} (pip install dembridge builds it; in a "
                 "source tree: cmake --build build --target mbdyn_testpeer)")
    os.execv(peer, [peer] + sys.argv[1:])


if __name__ == "__main__":
    main()
