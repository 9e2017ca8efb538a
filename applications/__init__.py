"""L3, applications: the state graph (XML), its condition language and checker, the state machine,
the dialog manager, the survey database, the tick loop and the command line. Imports only
`behaviors` (L2)."""
