namespace semgraph::core {}
