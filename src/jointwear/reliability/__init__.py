"""jointwear.reliability"""
