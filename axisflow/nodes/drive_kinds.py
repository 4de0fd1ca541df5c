"""The drives a bridge stack runs (:mod:`.bridge_stack`), in a module of their own: the command line's
parser offers them without loading the stack."""

DRIVES = ("sim", "canopen", "canopen-sim")
"""the built-in simulated axis; the CiA 402 drives of a drive.toml over CANopen; simulated CiA 402
drives hosted in the bridge's process"""
