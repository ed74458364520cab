"""Helpers of the coupled example scripts (examples/mbdyn_gate, examples/flexible_blade): the
MBDyn side (MBDyn or the test peer) runs as a child process next to LAMMPS."""
import os
import stat
import subprocess
import sys


def clear_stale_socket(sock, who):
    """Removes a socket file left at sock by a killed run (MBDyn would refuse to start on it);
    anything else there stops the script with a message naming who."""
    if os.path.lexists(sock):
        if not stat.S_ISSOCK(os.lstat(sock).st_mode):
            sys.exit(f"{who}: {sock} exists and is not a socket; remove it or choose another --out")
        os.unlink(sock)


def finish_mbdyn_side(proc, timeout=60):
    """Waits for the MBDyn side after LAMMPS has ended (killed after timeout s); its exit status."""
    try:
        proc.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
    return proc.returncode
