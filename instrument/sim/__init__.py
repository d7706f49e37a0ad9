"""The simulated lab: simulated devices for a protocol, the lab day, the simulated study, the demo."""
