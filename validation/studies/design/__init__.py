"""Inverse design and closed-loop control of the robotic surface."""
