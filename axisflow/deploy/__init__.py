"""Deployment: axisflow's processes (started, watched, stopped from one place), cells of axes around
one Zenoh router and their launch files, the security of a deployment (certificates, roles, the access
list), and the private network namespace of the runs that must not reach beyond the machine."""
