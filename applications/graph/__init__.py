"""The state graph of an application: its XML dialect, the data model it becomes, the checks that
run before anything moves, its pictures and its SCXML interchange.

Import the submodules directly (`applications.graph.loader`, `.model`, …)."""
